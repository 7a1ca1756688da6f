/* The dust walk's terms four lanes at a time with AVX2, the same IEEE
 * operations in the same order as orr_dust_meet and orr_dust_met_column
 * (column_walk.h), so each lane's term is the scalar code's bit for bit.
 * The lanes are four candidates of one star (column_group.c) or one
 * candidate of four stars (column_lanes.c). Internal to dust/; include it
 * only on x86-64 with GCC or Clang and without ORR_NO_CLONES (as both do). */
#ifndef ORR_DUST_COLUMN_AVX2_H
#define ORR_DUST_COLUMN_AVX2_H

#include <immintrin.h>

#include "core/simd.h"
#include "dust/column_walk.h"

#define AVX2_TARGET __attribute__((target("avx2")))

/* Four floats of a table at the indices i (four loads: AVX2's gather was
 * measured slower here). */
AVX2_TARGET static ORR_ALWAYS_INLINE __m128 load4(const float *table, __m128i i)
{
    int at[4];
    _mm_storeu_si128((__m128i *)at, i);
    return _mm_setr_ps(table[at[0]], table[at[1]], table[at[2]], table[at[3]]);
}

/* r0 + f (r1 - r0) as the scalar code computes it with r0 and r1 floats:
 * their difference in single precision, the rest in double. */
AVX2_TARGET static ORR_ALWAYS_INLINE __m256d lerp4(__m128 r0, __m128 r1, __m256d f)
{
    return _mm256_add_pd(_mm256_cvtps_pd(r0), _mm256_mul_pd(f, _mm256_cvtps_pd(_mm_sub_ps(r1, r0))));
}

/* orr_dust_half_column's operations, four at a time: I(beta, |sv|). */
AVX2_TARGET static ORR_ALWAYS_INLINE __m256d half_columns4(const float *pcol, __m256d beta, __m256d sv)
{
    const __m256d u = _mm256_mul_pd(beta, _mm256_set1_pd(ORR_DUST_PCOL_NB / ORR_DUST_SUPPORT));
    __m256d v = _mm256_mul_pd(_mm256_andnot_pd(_mm256_set1_pd(-0.0), sv),
                              _mm256_set1_pd(ORR_DUST_PCOL_NS / ORR_DUST_SUPPORT));
    v = _mm256_blendv_pd(v, _mm256_set1_pd(ORR_DUST_PCOL_NS - 1e-9),
                         _mm256_cmp_pd(v, _mm256_set1_pd(ORR_DUST_PCOL_NS), _CMP_GE_OQ));
    const __m128i i = _mm_min_epi32(_mm256_cvttpd_epi32(u), _mm_set1_epi32(ORR_DUST_PCOL_NB - 1));
    const __m128i j = _mm256_cvttpd_epi32(v);
    const __m256d fu = _mm256_sub_pd(u, _mm256_cvtepi32_pd(i)), fv = _mm256_sub_pd(v, _mm256_cvtepi32_pd(j));
    const int cols = ORR_DUST_PCOL_NS + 1;
    const __m128i at = _mm_add_epi32(_mm_mullo_epi32(i, _mm_set1_epi32(cols)), j);
    const __m256d a = lerp4(load4(pcol, at), load4(pcol + 1, at), fv);
    const __m256d b = lerp4(load4(pcol + cols, at), load4(pcol + cols + 1, at), fv);
    return _mm256_add_pd(a, _mm256_mul_pd(fu, _mm256_sub_pd(b, a)));
}

/* orr_dust_pcol_given's operations, four at a time, for the met lanes (the
 * others' values are not used) at the segment's end s1 (start 0: the whole
 * column where it lies beyond the support) or its start s0 (start 1: 0
 * where it lies before it), F / 2 +- I(beta, |sv|) inside: looked up only
 * if a met lane is inside. */
AVX2_TARGET static ORR_ALWAYS_INLINE __m256d pcols_given4(const float *pcol, __m256d whole, __m256d beta,
                                                          __m256d sv, __m256d met, int start)
{
    const __m256d support = _mm256_set1_pd(ORR_DUST_SUPPORT), zero = _mm256_setzero_pd();
    const __m256d inside = start ? _mm256_cmp_pd(sv, _mm256_sub_pd(zero, support), _CMP_GT_OQ)
                                 : _mm256_cmp_pd(sv, support, _CMP_LT_OQ);
    const __m256d outside = start ? zero : whole;
    if (!_mm256_movemask_pd(_mm256_and_pd(inside, met)))
        return outside;
    const __m256d h = half_columns4(pcol, beta, sv);
    const __m256d negative = _mm256_cmp_pd(sv, zero, _CMP_LT_OQ);
    const __m256d half = _mm256_add_pd(_mm256_mul_pd(whole, _mm256_set1_pd(0.5)),
                                       _mm256_blendv_pd(h, _mm256_xor_pd(h, _mm256_set1_pd(-0.0)), negative));
    return _mm256_blendv_pd(outside, half, inside);
}

/* orr_dust_met_column's partial branch, four at a time, given the whole
 * columns: P(s1) - P(s0). */
AVX2_TARGET static ORR_ALWAYS_INLINE __m256d partial_columns4(const float *pcol, __m256d whole, __m256d u,
                                                              __m256d s0, __m256d s1, __m256d met)
{
    const __m256d beta = _mm256_sqrt_pd(u);
    return _mm256_sub_pd(pcols_given4(pcol, whole, beta, s1, met, 0), pcols_given4(pcol, whole, beta, s0, met, 1));
}

/* Where four segments pass four kernels, orr_dust_meet's operations lane
 * by lane: the kernels' centres v = (vx, vy, vz) from the eye (v2 = |v|^2)
 * and 1/h = ih, the segments' unit directions d and lengths len. Sets u,
 * s0 and s1 (in units of h) and returns the lanes whose segment meets its
 * kernel's support (all bits set), without a branch: whether a kernel is
 * met is a coin toss for the branch predictor. */
AVX2_TARGET static ORR_ALWAYS_INLINE __m256d meet4(__m256d vx, __m256d vy, __m256d vz, __m256d v2, __m256d ih,
                                                   const __m256d d[3], __m256d len, __m256d *u, __m256d *s0,
                                                   __m256d *s1)
{
    const __m256d zero = _mm256_setzero_pd(), support = _mm256_set1_pd(ORR_DUST_SUPPORT);
    const __m256d tc =
        _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(vx, d[0]), _mm256_mul_pd(vy, d[1])), _mm256_mul_pd(vz, d[2]));
    const __m256d b2 = _mm256_sub_pd(v2, _mm256_mul_pd(tc, tc));
    *u = _mm256_mul_pd(_mm256_mul_pd(_mm256_and_pd(b2, _mm256_cmp_pd(b2, zero, _CMP_GT_OQ)), ih), ih);
    *s0 = _mm256_mul_pd(_mm256_xor_pd(tc, _mm256_set1_pd(-0.0)), ih);
    *s1 = _mm256_mul_pd(_mm256_sub_pd(len, tc), ih);
    const __m256d end =
        _mm256_blendv_pd(_mm256_and_pd(_mm256_mul_pd(*s0, *s0), _mm256_cmp_pd(*s0, zero, _CMP_GT_OQ)),
                         _mm256_mul_pd(*s1, *s1), _mm256_cmp_pd(*s1, zero, _CMP_LT_OQ));
    return _mm256_cmp_pd(_mm256_add_pd(*u, end), _mm256_mul_pd(support, support), _CMP_LT_OQ);
}

/* orr_dust_met_column's operations times k/h^2 = kih2 for the met lanes
 * (meet4), 0 in the others. A met kernel's u is below 4, so its whole
 * column's index is inside the table; the others' are set to 0 before the
 * look-up. Most met kernels are crossed whole (the eye and the star
 * outside them); the partial columns are computed only for four lanes
 * that hold one. */
AVX2_TARGET static ORR_ALWAYS_INLINE __m256d met_terms4(const orr_dust_set *s, __m256d u, __m256d s0, __m256d s1,
                                                        __m256d met, __m256d kih2)
{
    const __m256d zero = _mm256_setzero_pd(), support = _mm256_set1_pd(ORR_DUST_SUPPORT);
    const __m256d x = _mm256_and_pd(
        _mm256_mul_pd(u, _mm256_set1_pd(ORR_DUST_FCOL_NU / (ORR_DUST_SUPPORT * ORR_DUST_SUPPORT))), met);
    const __m128i i = _mm256_cvttpd_epi32(x);
    const __m256d f = _mm256_sub_pd(x, _mm256_cvtepi32_pd(i));
    __m256d col = lerp4(load4(s->fcol, i), load4(s->fcol + 1, i), f);
    const __m256d crossed = _mm256_and_pd(_mm256_cmp_pd(s0, _mm256_sub_pd(zero, support), _CMP_LE_OQ),
                                          _mm256_cmp_pd(s1, support, _CMP_GE_OQ));
    if (_mm256_movemask_pd(_mm256_andnot_pd(crossed, met)))
        col = _mm256_blendv_pd(partial_columns4(s->pcol, col, _mm256_and_pd(u, met), s0, s1, met), col, crossed);
    return _mm256_and_pd(_mm256_mul_pd(kih2, col), met);
}

#endif
