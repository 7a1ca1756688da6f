/* A small counter-based random generator for the built-in model.
 *
 * Algorithm: SplitMix64 (G. L. Steele, D. Lea, C. H. Flood, "Fast splittable
 * pseudorandom number generators", OOPSLA 2014; the constants are those of
 * S. Vigna's public-domain reference splitmix64.c). The state is a 64-bit
 * counter that advances by the golden-ratio increment; each output is the
 * counter passed through a bijective 64-bit finaliser.
 *
 * Why counter-based: the model generates particle i from a generator keyed by
 * (seed, i, stream) alone, so any particle can be produced without producing
 * the ones before it and the output does not depend on how the particles are
 * split into chunks. Written here from the published algorithm.
 *
 * Not for cryptography. Header-only: everything is small and inlined into the
 * generator's inner loop. */
#ifndef ORR_SOURCE_RNG_H
#define ORR_SOURCE_RNG_H

#include <math.h>
#include <stdint.h>

#define ORR_RNG_GAMMA 0x9E3779B97F4A7C15ULL /* 2^64 / golden ratio, odd */

typedef struct orr_rng {
    uint64_t state;
} orr_rng;

/* The SplitMix64 finaliser (a variant of MurmurHash3's fmix64): a bijection
 * on 64-bit integers with good avalanche, so nearby inputs give unrelated
 * outputs. */
static inline uint64_t orr_rng_mix(uint64_t z)
{
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    return z ^ (z >> 31);
}

/* A generator keyed by (seed, index, stream). Each key component goes through
 * the finaliser before the next is added, so e.g. (seed, index + 1) and
 * (seed + 1, index) give unrelated keys. Sequences of different keys start at
 * effectively random points of the 2^64 cycle; overlaps between the short
 * per-particle sequences are vanishingly unlikely. */
static inline orr_rng orr_rng_seed(uint64_t seed, uint64_t index, uint64_t stream)
{
    uint64_t k = orr_rng_mix(seed + ORR_RNG_GAMMA);
    k = orr_rng_mix(k + index);
    k = orr_rng_mix(k + stream);
    return (orr_rng){k};
}

static inline uint64_t orr_rng_next(orr_rng *r)
{
    r->state += ORR_RNG_GAMMA;
    return orr_rng_mix(r->state);
}

/* A uniform double in the open interval (0, 1): the top 53 bits plus one
 * half, so neither 0 nor 1 can occur and log(u), 1/(1 - u) are always
 * finite. */
static inline double orr_rng_uniform(orr_rng *r)
{
    return ((double)(orr_rng_next(r) >> 11) + 0.5) * (1.0 / 9007199254740992.0);
}

/* Two independent standard normal deviates (Box-Muller transform). */
static inline void orr_rng_gauss2(orr_rng *r, double *g0, double *g1)
{
    double rad = sqrt(-2.0 * log(orr_rng_uniform(r)));
    double ang = 6.283185307179586 * orr_rng_uniform(r);
    *g0 = rad * cos(ang);
    *g1 = rad * sin(ang);
}

#endif
