/* A string -> index hash table (open addressing, FNV-1a), so that looking up object
 * and material names costs O(1) per OBJ statement instead of a scan of all names. */
#ifndef RESTIR_NAME_TABLE_H
#define RESTIR_NAME_TABLE_H

#include <stddef.h>
#include <stdint.h>
#include "restir/core/error.h"

typedef struct {
    char **keys;      /* owned copies; NULL = empty slot */
    uint32_t *values;
    size_t capacity;  /* a power of two, or 0 */
    size_t count;
} name_table;

/* The value stored for key, or -1. */
long name_table_find(const name_table *t, const char *key);
/* Stores a copy of key (which must not be present yet) with its value. */
int name_table_insert(name_table *t, const char *key, uint32_t value, rerror *e);
void name_table_free(name_table *t);

#endif
