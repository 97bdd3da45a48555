/* String -> index hash table with linear probing; grows at half load. */
#include "restir/scene/name_table.h"

#include <stdlib.h>
#include <string.h>

static uint64_t fnv1a(const char *s)
{
    uint64_t h = 14695981039346656037ULL;
    while (*s) {
        h ^= (unsigned char)*s++;
        h *= 1099511628211ULL;
    }
    return h;
}

long name_table_find(const name_table *t, const char *key)
{
    size_t mask, i;
    if (!t->capacity) return -1;
    mask = t->capacity - 1;
    for (i = (size_t)fnv1a(key) & mask; t->keys[i]; i = (i + 1) & mask)
        if (!strcmp(t->keys[i], key)) return (long)t->values[i];
    return -1;
}

static void place(char **keys, uint32_t *values, size_t capacity, char *key, uint32_t value)
{
    size_t mask = capacity - 1, i = (size_t)fnv1a(key) & mask;
    while (keys[i]) i = (i + 1) & mask;
    keys[i] = key;
    values[i] = value;
}

static int grow(name_table *t, rerror *e)
{
    size_t capacity = t->capacity ? t->capacity * 2 : 64, i;
    char **keys = rcalloc(capacity, sizeof *keys, e);
    uint32_t *values = rcalloc(capacity, sizeof *values, e);
    if (!keys || !values) {
        free(keys);
        free(values);
        return -1;
    }
    for (i = 0; i < t->capacity; ++i)
        if (t->keys[i]) place(keys, values, capacity, t->keys[i], t->values[i]);
    free(t->keys);
    free(t->values);
    t->keys = keys;
    t->values = values;
    t->capacity = capacity;
    return 0;
}

int name_table_insert(name_table *t, const char *key, uint32_t value, rerror *e)
{
    size_t n = strlen(key);
    char *copy;
    if ((t->count + 1) * 2 > t->capacity && grow(t, e)) return -1;
    copy = rmalloc(n + 1, 1, e);
    if (!copy) return -1;
    memcpy(copy, key, n + 1);
    place(t->keys, t->values, t->capacity, copy, value);
    t->count++;
    return 0;
}

void name_table_free(name_table *t)
{
    size_t i;
    for (i = 0; i < t->capacity; ++i) free(t->keys[i]);
    free(t->keys);
    free(t->values);
    memset(t, 0, sizeof *t);
}
