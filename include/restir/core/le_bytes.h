/* Little-endian encoding over a moving cursor: the one implementation behind the binary
 * formats of docs/formats.md (reservoir dumps, stage dumps, G-buffer dumps). Floats are
 * stored as their IEEE-754 bit patterns; `real` values are always stored as binary64. */
#ifndef RESTIR_LE_BYTES_H
#define RESTIR_LE_BYTES_H

#include <stdint.h>
#include "restir/core/vec.h"

void le_put_u8(unsigned char **p, unsigned v);
void le_put_u32(unsigned char **p, uint32_t v);
void le_put_u64(unsigned char **p, uint64_t v);
void le_put_f32(unsigned char **p, float f);
void le_put_f64(unsigned char **p, double d);
void le_put_vec3f(unsigned char **p, vec3f v);

unsigned le_get_u8(const unsigned char **p);
uint32_t le_get_u32(const unsigned char **p);
uint64_t le_get_u64(const unsigned char **p);
float le_get_f32(const unsigned char **p);
double le_get_f64(const unsigned char **p);
vec3f le_get_vec3f(const unsigned char **p);

#endif
