/* A chunk of particles in structure-of-arrays layout. Sources hand particles
 * to the renderer one chunk at a time, so memory stays bounded for any N.
 * Positions, masses and smoothing lengths are float: snapshot formats store
 * them so, and the splat loop is bound by memory bandwidth. */
#ifndef ORR_PARTICLES_CHUNK_H
#define ORR_PARTICLES_CHUNK_H

#include <stddef.h>
#include <stdint.h>

#include "core/error.h"

#define ORR_FIELD_NAME_MAX 32
#define ORR_MAX_EXTRA_FIELDS 16

typedef struct orr_extra_field {
    char name[ORR_FIELD_NAME_MAX];
    float *data;
} orr_extra_field;

typedef struct orr_chunk {
    size_t n;             /* particles in use */
    size_t capacity;      /* particles the arrays can hold */
    uint64_t first_index; /* position in the source of particle 0 (for messages) */
    float *x, *y, *z;
    float *mass;
    float *h;      /* smoothing length; NULL when the source has none */
    uint64_t *id;  /* ids; sources without ids number particles from 0 */
    uint8_t *type; /* particle type, Gadget convention 0..5; 0 when the source has none */
    int nextra;
    orr_extra_field extra[ORR_MAX_EXTRA_FIELDS];
} orr_chunk;

/* Allocates arrays for capacity particles: x, y, z, mass, id and type always,
 * h when with_h, and one float array per extra field name. */
orr_status orr_chunk_alloc(orr_chunk *c, size_t capacity, int with_h,
                           const char *const *extra_names, int nextra, orr_error *err);
void orr_chunk_free(orr_chunk *c);

/* The float array of a field by name: "x", "y", "z", "mass", "h" or an extra
 * field; NULL when the chunk has no such field. */
float *orr_chunk_field(const orr_chunk *c, const char *name);

/* Index (within the chunk) of the first particle whose position is NaN or
 * infinite, or -1 when every position is finite. */
long orr_chunk_first_nonfinite(const orr_chunk *c, size_t start);

/* Removes particle i by moving the last particle into its place. */
void orr_chunk_remove(orr_chunk *c, size_t i);

#endif
