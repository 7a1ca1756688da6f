/* Eight stars' optical depths at once, a star a lane (column_lanes.h).
 *
 * Every lane does orr_dust_meet's and orr_dust_met_column's IEEE
 * operations (column_walk.h) in their order, so a lane's sum is its star's
 * own walk's bit for bit (tests/unit/test_dust.c compares them): in one
 * AVX-512 register, or in two halves of four with AVX2. */
#include "dust/column_lanes.h"

#include "core/simd.h"
#include "dust/column_walk.h"

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__)) && !defined(ORR_NO_CLONES)
#define HAVE_STAR_LANES 1
#include <immintrin.h>
#endif

#ifdef HAVE_STAR_LANES
#define LANES_TARGET __attribute__((target("avx512f,avx2")))

/* Eight floats of a table at the indices i, as doubles' worth of floats:
 * one gather, measured as fast as eight loads (for four, load4's loads
 * were faster than a gather). */
LANES_TARGET static ORR_ALWAYS_INLINE __m256 load8(const float *table, __m256i i)
{
    return _mm256_i32gather_ps(table, i, 4);
}

/* r0 + f (r1 - r0) with r0 and r1 floats: their difference in single
 * precision, the rest in double (as the scalar code). */
LANES_TARGET static ORR_ALWAYS_INLINE __m512d lerp8(__m256 r0, __m256 r1, __m512d f)
{
    return _mm512_add_pd(_mm512_cvtps_pd(r0), _mm512_mul_pd(f, _mm512_cvtps_pd(_mm256_sub_ps(r1, r0))));
}

/* -x, by its sign bit, the bits of -0.0 (AVX-512F has no floating-point
 * xor). */
LANES_TARGET static ORR_ALWAYS_INLINE __m512d negate8(__m512d x)
{
    return _mm512_castsi512_pd(
        _mm512_xor_si512(_mm512_castpd_si512(x), _mm512_castpd_si512(_mm512_set1_pd(-0.0))));
}

/* orr_dust_half_column: I(beta, |sv|). */
LANES_TARGET static ORR_ALWAYS_INLINE __m512d half_columns8(const float *pcol, __m512d beta, __m512d sv)
{
    const __m512d u = _mm512_mul_pd(beta, _mm512_set1_pd(ORR_DUST_PCOL_NB / ORR_DUST_SUPPORT));
    __m512d v = _mm512_mul_pd(_mm512_abs_pd(sv), _mm512_set1_pd(ORR_DUST_PCOL_NS / ORR_DUST_SUPPORT));
    v = _mm512_mask_mov_pd(v, _mm512_cmp_pd_mask(v, _mm512_set1_pd(ORR_DUST_PCOL_NS), _CMP_GE_OQ),
                           _mm512_set1_pd(ORR_DUST_PCOL_NS - 1e-9));
    const __m256i i = _mm256_min_epi32(_mm512_cvttpd_epi32(u), _mm256_set1_epi32(ORR_DUST_PCOL_NB - 1));
    const __m256i j = _mm512_cvttpd_epi32(v);
    const __m512d fu = _mm512_sub_pd(u, _mm512_cvtepi32_pd(i)), fv = _mm512_sub_pd(v, _mm512_cvtepi32_pd(j));
    const int cols = ORR_DUST_PCOL_NS + 1;
    const __m256i at = _mm256_add_epi32(_mm256_mullo_epi32(i, _mm256_set1_epi32(cols)), j);
    const __m512d a = lerp8(load8(pcol, at), load8(pcol + 1, at), fv);
    const __m512d b = lerp8(load8(pcol + cols, at), load8(pcol + cols + 1, at), fv);
    return _mm512_add_pd(a, _mm512_mul_pd(fu, _mm512_sub_pd(b, a)));
}

/* orr_dust_pcol_given's operations for the met lanes at the segment's end
 * s1 (start 0: the whole column where it lies beyond the support) or its
 * start s0 (start 1: 0 where it lies before it), F / 2 +- I(beta, |sv|)
 * inside: looked up only if a met lane is inside. */
LANES_TARGET static ORR_ALWAYS_INLINE __m512d pcols_given8(const float *pcol, __m512d whole, __m512d beta,
                                                           __m512d sv, __mmask8 met, int start)
{
    const __m512d support = _mm512_set1_pd(ORR_DUST_SUPPORT), zero = _mm512_setzero_pd();
    const __mmask8 inside = start ? _mm512_cmp_pd_mask(sv, _mm512_sub_pd(zero, support), _CMP_GT_OQ)
                                  : _mm512_cmp_pd_mask(sv, support, _CMP_LT_OQ);
    const __m512d outside = start ? zero : whole;
    if (!(inside & met))
        return outside;
    const __m512d h = half_columns8(pcol, beta, sv);
    const __mmask8 negative = _mm512_cmp_pd_mask(sv, zero, _CMP_LT_OQ);
    const __m512d half =
        _mm512_add_pd(_mm512_mul_pd(whole, _mm512_set1_pd(0.5)), _mm512_mask_mov_pd(h, negative, negate8(h)));
    return _mm512_mask_mov_pd(outside, inside, half);
}

/* orr_dust_met_column's partial branch, given the whole columns: P(s1) -
 * P(s0). */
LANES_TARGET static ORR_ALWAYS_INLINE __m512d partial_columns8(const float *pcol, __m512d whole, __m512d u,
                                                               __m512d s0, __m512d s1, __mmask8 met)
{
    const __m512d beta = _mm512_sqrt_pd(u);
    return _mm512_sub_pd(pcols_given8(pcol, whole, beta, s1, met, 0), pcols_given8(pcol, whole, beta, s0, met, 1));
}

/* Candidate j's terms on the eight segments, added to sum: 0 (and nothing
 * added) where a segment misses its support. */
LANES_TARGET static ORR_ALWAYS_INLINE __m512d add_terms8(const orr_dust_set *s, const orr_dust_candidate_view *c,
                                                         size_t j, const __m512d d[3], __m512d len, __m512d sum)
{
    const __m512d zero = _mm512_setzero_pd(), support = _mm512_set1_pd(ORR_DUST_SUPPORT);
    const __m512d tc = _mm512_add_pd(_mm512_add_pd(_mm512_mul_pd(_mm512_set1_pd(c->vx[j]), d[0]),
                                                   _mm512_mul_pd(_mm512_set1_pd(c->vy[j]), d[1])),
                                     _mm512_mul_pd(_mm512_set1_pd(c->vz[j]), d[2]));
    const __m512d b2 = _mm512_sub_pd(_mm512_set1_pd(c->v2[j]), _mm512_mul_pd(tc, tc));
    const __m512d ih = _mm512_set1_pd((double)c->ih[j]);
    const __m512d u =
        _mm512_mul_pd(_mm512_mul_pd(_mm512_maskz_mov_pd(_mm512_cmp_pd_mask(b2, zero, _CMP_GT_OQ), b2), ih), ih);
    const __m512d s0 = _mm512_mul_pd(negate8(tc), ih);
    const __m512d s1 = _mm512_mul_pd(_mm512_sub_pd(len, tc), ih);
    const __m512d end =
        _mm512_mask_mov_pd(_mm512_maskz_mov_pd(_mm512_cmp_pd_mask(s0, zero, _CMP_GT_OQ), _mm512_mul_pd(s0, s0)),
                           _mm512_cmp_pd_mask(s1, zero, _CMP_LT_OQ), _mm512_mul_pd(s1, s1));
    const __mmask8 met =
        _mm512_cmp_pd_mask(_mm512_add_pd(u, end), _mm512_mul_pd(support, support), _CMP_LT_OQ);
    if (!met)
        return sum; /* adding 0 to a sum >= 0 changes no bit */
    const __m512d x = _mm512_maskz_mov_pd(
        met, _mm512_mul_pd(u, _mm512_set1_pd(ORR_DUST_FCOL_NU / (ORR_DUST_SUPPORT * ORR_DUST_SUPPORT))));
    const __m256i i = _mm512_cvttpd_epi32(x);
    const __m512d f = _mm512_sub_pd(x, _mm512_cvtepi32_pd(i));
    __m512d col = lerp8(load8(s->fcol, i), load8(s->fcol + 1, i), f);
    const __mmask8 crossed = _mm512_cmp_pd_mask(s0, _mm512_sub_pd(zero, support), _CMP_LE_OQ) &
                             _mm512_cmp_pd_mask(s1, support, _CMP_GE_OQ);
    if (met & ~crossed)
        col = _mm512_mask_mov_pd(partial_columns8(s->pcol, col, _mm512_maskz_mov_pd(met, u), s0, s1, met), crossed,
                                 col);
    const __m512d term = _mm512_mul_pd(_mm512_set1_pd((double)c->kih2[j]), col);
    return _mm512_mask_add_pd(sum, met, sum, term);
}

LANES_TARGET static void lanes_tau_avx512(const orr_dust_set *s, const orr_dust_candidate_view *c,
                                          const orr_dust_star_lanes *g, double tau[ORR_DUST_STAR_LANES])
{
    const __m512d d[3] = {_mm512_loadu_pd(g->d[0]), _mm512_loadu_pd(g->d[1]), _mm512_loadu_pd(g->d[2])};
    const __m512d len = _mm512_loadu_pd(g->len);
    __m512d sum = _mm512_setzero_pd();
    for (size_t j = 0; j < c->n; j++)
        sum = add_terms8(s, c, j, d, len, sum);
    _mm512_storeu_pd(tau, sum);
}
/* ---- eight stars in two halves of four lanes, with AVX2 ---- */

#define AVX2_TARGET __attribute__((target("avx2")))

/* Four floats of a table at the indices i (four loads: AVX2's gather was
 * measured slower, docs/dust.md#cost). */
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

/* Candidate j's terms on the eight segments, two halves of four lanes
 * (d, len), added to sum: a half none of whose segments meets the kernel's
 * support costs only the test. */
AVX2_TARGET static ORR_ALWAYS_INLINE void add_terms_halves(const orr_dust_set *s, const orr_dust_candidate_view *c,
                                                           size_t j, const __m256d d[2][3], const __m256d len[2],
                                                           __m256d sum[2])
{
    const __m256d vx = _mm256_set1_pd(c->vx[j]), vy = _mm256_set1_pd(c->vy[j]), vz = _mm256_set1_pd(c->vz[j]);
    const __m256d v2 = _mm256_set1_pd(c->v2[j]), ih = _mm256_set1_pd((double)c->ih[j]);
    __m256d u[2], s0[2], s1[2], met[2];
    for (int h = 0; h < 2; h++)
        met[h] = meet4(vx, vy, vz, v2, ih, d[h], len[h], &u[h], &s0[h], &s1[h]);
    if (!_mm256_movemask_pd(_mm256_or_pd(met[0], met[1])))
        return;
    const __m256d kih2 = _mm256_set1_pd((double)c->kih2[j]);
    for (int h = 0; h < 2; h++)
        sum[h] = _mm256_add_pd(sum[h], met_terms4(s, u[h], s0[h], s1[h], met[h], kih2));
}

AVX2_TARGET static void lanes_tau_avx2(const orr_dust_set *s, const orr_dust_candidate_view *c,
                                       const orr_dust_star_lanes *g, double tau[ORR_DUST_STAR_LANES])
{
    __m256d d[2][3], len[2], sum[2];
    for (int h = 0; h < 2; h++) {
        for (int a = 0; a < 3; a++)
            d[h][a] = _mm256_loadu_pd(g->d[a] + 4 * h);
        len[h] = _mm256_loadu_pd(g->len + 4 * h);
        sum[h] = _mm256_setzero_pd();
    }
    for (size_t j = 0; j < c->n; j++)
        add_terms_halves(s, c, j, d, len, sum);
    _mm256_storeu_pd(tau, sum[0]);
    _mm256_storeu_pd(tau + 4, sum[1]);
}
#endif

int orr_dust_star_lanes_runs(orr_dust_lanes_way way)
{
#ifdef HAVE_STAR_LANES
    if (way == ORR_DUST_LANES_AVX512)
        return __builtin_cpu_supports("avx512f");
    if (way == ORR_DUST_LANES_AVX2)
        return __builtin_cpu_supports("avx2");
#endif
    return way == ORR_DUST_LANES_PLAIN;
}

orr_dust_lanes_way orr_dust_star_lanes_best(void)
{
    return orr_dust_star_lanes_runs(ORR_DUST_LANES_AVX512) ? ORR_DUST_LANES_AVX512
           : orr_dust_star_lanes_runs(ORR_DUST_LANES_AVX2) ? ORR_DUST_LANES_AVX2
                                                           : ORR_DUST_LANES_PLAIN;
}

/* Lane l's sum one term at a time: the same bits. */
static double lane_tau_plain(const orr_dust_set *s, const orr_dust_candidate_view *c, const orr_dust_star_lanes *g,
                             int l)
{
    const orr_dust_segment seg = {.d = {g->d[0][l], g->d[1][l], g->d[2][l]}, .len = g->len[l]};
    double sum = 0;
    for (size_t j = 0; j < c->n; j++)
        sum += orr_dust_term(s, &seg, c->vx[j], c->vy[j], c->vz[j], c->v2[j], c->ih[j], c->kih2[j]);
    return sum;
}

void orr_dust_star_lanes_tau(orr_dust_lanes_way way, const orr_dust_set *s, const orr_dust_candidate_view *c,
                             const orr_dust_star_lanes *g, double tau[ORR_DUST_STAR_LANES])
{
#ifdef HAVE_STAR_LANES
    if (way == ORR_DUST_LANES_AVX512 && orr_dust_star_lanes_runs(way)) {
        lanes_tau_avx512(s, c, g, tau);
        return;
    }
    if (way == ORR_DUST_LANES_AVX2 && orr_dust_star_lanes_runs(way)) {
        lanes_tau_avx2(s, c, g, tau);
        return;
    }
#endif
    for (int l = 0; l < ORR_DUST_STAR_LANES; l++)
        tau[l] = lane_tau_plain(s, c, g, l);
}
