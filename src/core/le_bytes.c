/* Little-endian encoding over a moving cursor (include/restir/core/le_bytes.h). */
#include "restir/core/le_bytes.h"

#include <string.h>

void le_put_u8(unsigned char **p, unsigned v) { *(*p)++ = (unsigned char)(v & 0xffu); }

void le_put_u32(unsigned char **p, uint32_t v)
{
    int i;
    for (i = 0; i < 4; ++i) le_put_u8(p, (unsigned)(v >> (8 * i)));
}

void le_put_u64(unsigned char **p, uint64_t v)
{
    int i;
    for (i = 0; i < 8; ++i) le_put_u8(p, (unsigned)(v >> (8 * i)));
}

void le_put_f32(unsigned char **p, float f)
{
    uint32_t bits;
    memcpy(&bits, &f, sizeof bits);
    le_put_u32(p, bits);
}

void le_put_f64(unsigned char **p, double d)
{
    uint64_t bits;
    memcpy(&bits, &d, sizeof bits);
    le_put_u64(p, bits);
}

void le_put_vec3f(unsigned char **p, vec3f v)
{
    le_put_f32(p, v.x);
    le_put_f32(p, v.y);
    le_put_f32(p, v.z);
}

unsigned le_get_u8(const unsigned char **p) { return *(*p)++; }

uint32_t le_get_u32(const unsigned char **p)
{
    uint32_t v = 0;
    int i;
    for (i = 0; i < 4; ++i) v |= (uint32_t)le_get_u8(p) << (8 * i);
    return v;
}

uint64_t le_get_u64(const unsigned char **p)
{
    uint64_t v = 0;
    int i;
    for (i = 0; i < 8; ++i) v |= (uint64_t)le_get_u8(p) << (8 * i);
    return v;
}

float le_get_f32(const unsigned char **p)
{
    uint32_t bits = le_get_u32(p);
    float f;
    memcpy(&f, &bits, sizeof f);
    return f;
}

double le_get_f64(const unsigned char **p)
{
    uint64_t bits = le_get_u64(p);
    double d;
    memcpy(&d, &bits, sizeof d);
    return d;
}

vec3f le_get_vec3f(const unsigned char **p)
{
    vec3f v;
    v.x = le_get_f32(p);
    v.y = le_get_f32(p);
    v.z = le_get_f32(p);
    return v;
}
