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

/* The seed's part of that key, the same for every index: a generator that
 * keys many particles takes it once (orr_rng_seed_keyed gives the same
 * generator as orr_rng_seed). */
static inline uint64_t orr_rng_seed_key(uint64_t seed)
{
    return orr_rng_mix(seed + ORR_RNG_GAMMA);
}

static inline orr_rng orr_rng_seed_keyed(uint64_t seed_key, uint64_t index, uint64_t stream)
{
    return (orr_rng){orr_rng_mix(orr_rng_mix(seed_key + index) + stream)};
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
    /* below 2^53, so the signed conversion (one instruction; the unsigned
     * one is a branchy sequence) gives the same double */
    return ((double)(int64_t)(orr_rng_next(r) >> 11) + 0.5) * (1.0 / 9007199254740992.0);
}

/* Two independent standard normal deviates (Box-Muller transform). */
static inline void orr_rng_gauss2(orr_rng *r, double *g0, double *g1)
{
    double rad = sqrt(-2.0 * log(orr_rng_uniform(r)));
    double ang = 6.283185307179586 * orr_rng_uniform(r);
    *g0 = rad * cos(ang);
    *g1 = rad * sin(ang);
}

/* sin and cos of 2 pi u for u in [0, 1] (a "turn"), without the general
 * argument reduction of libm's sincos: u less its nearest quarter, t in
 * [-1/8, 1/8], is exact in double (u is a multiple of 2^-54), x = 2 pi t
 * lies in [-pi/4, pi/4], where the Taylor series to x^15 (sin) and x^16
 * (cos) are within 5e-17 of the functions, and the quarter turns are
 * exact swaps and sign changes. Within a few 1e-16 of sin(2 pi u) and
 * cos(2 pi u) (rounding of x and of the sums), at a quarter of the cost. */
static inline void orr_sincos_turn(double u, double *s, double *c)
{
    int k = (int)(4.0 * u + 0.5); /* u >= 0: truncation rounds */
    double x = (u - 0.25 * k) * 6.283185307179586, y = x * x, y2 = y * y, y4 = y2 * y2;
    /* Estrin's scheme: the series in pairs, so the chain is short */
    double s01 = 1.0 - y * (1.0 / 6), s23 = 1.0 / 120 - y * (1.0 / 5040);
    double s45 = 1.0 / 362880 - y * (1.0 / 39916800), s67 = 1.0 / 6227020800.0 - y * (1.0 / 1307674368000.0);
    double sx = x * ((s01 + y2 * s23) + y4 * (s45 + y2 * s67));
    double c01 = 1.0 - y * 0.5, c23 = 1.0 / 24 - y * (1.0 / 720);
    double c45 = 1.0 / 40320 - y * (1.0 / 3628800), c67 = 1.0 / 479001600.0 - y * (1.0 / 87178291200.0);
    double cx = (c01 + y2 * c23) + y4 * ((c45 + y2 * c67) + y4 * (1.0 / 20922789888000.0));
    /* quarter k: odd ones swap the two, and the sine's sign flips in the
     * third and fourth, the cosine's in the second and third (selects, no
     * branch, so a loop of these vectorises) */
    double s0 = (k & 1) ? cx : sx, c0 = (k & 1) ? sx : cx;
    *s = (k & 2) ? -s0 : s0;
    *c = ((k + 1) & 2) ? -c0 : c0;
}

/* orr_rng_gauss2 with orr_sincos_turn: the same two deviates to a few
 * 1e-16 (relative), for the tabulated model. */
static inline void orr_rng_gauss2_fast(orr_rng *r, double *g0, double *g1)
{
    double rad = sqrt(-2.0 * log(orr_rng_uniform(r))), sn, cs;
    orr_sincos_turn(orr_rng_uniform(r), &sn, &cs);
    *g0 = rad * cs;
    *g1 = rad * sn;
}

#endif
