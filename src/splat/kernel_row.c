#include "splat/kernel_row.h"

#include "core/simd.h"

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__)) && !defined(ORR_NO_CLONES)
#define HAVE_VECTOR_ROWS 1
#include <immintrin.h>
#endif

enum { DEGREE = ORR_KERNEL_POLY_DEGREE, PIECES = ORR_KERNEL_POLY_PIECES };

/* t = 32 is the edge of the support (u = 4). */
#define T_EDGE (4.0f * ORR_KERNEL_POLY_T)

void orr_sample_poly_make(orr_sample_poly *p, const orr_kernel *k, float lap)
{
    for (int d = 0; d <= DEGREE; d++)
        for (int q = 0; q < PIECES; q++)
            p->c[d][q] = k->poly_f[d * PIECES + q] + lap * k->poly_lap[d * PIECES + q];
}

/* Every path below computes a sample exactly so: the same operations in
 * the same order, none fused (the build does not contract, CMakeLists.txt),
 * so the vector loop and the plain one agree to the bit. */
static ORR_ALWAYS_INLINE float sample_at(const orr_sample_poly *p, float t)
{
    float x;
    const int piece = orr_kernel_poly_piece(t, &x);
    float s = p->c[DEGREE][piece];
    for (int d = DEGREE - 1; d >= 0; d--)
        s = s * x + p->c[d][piece];
    return t < T_EDGE ? s : 0.0f;
}

float orr_sample_poly_at(const orr_sample_poly *p, float t)
{
    return sample_at(p, t);
}

/* t of sample m: the ellipse's quadratic form at dx, times 8 (exact). */
static ORR_ALWAYS_INLINE float sample_t(float a, float bdy, float cdy, float dx)
{
    return ((a * dx + bdy) * dx + cdy) * ORR_KERNEL_POLY_T;
}

/* The mode is a constant in each inlined copy, so the loops have no
 * branch and the compiler vectorises them (gathering the coefficients). */
static ORR_ALWAYS_INLINE void plain_loop(const orr_sample_poly *p, float a, float bdy, float cdy, float dx0, int m0,
                                         int m1, float *restrict out, orr_sample_mode mode, float scale)
{
    for (int m = m0; m < m1; m++) {
        const float s = sample_at(p, sample_t(a, bdy, cdy, dx0 + (float)m));
        if (mode == ORR_SAMPLES_DRAW)
            out[m] += scale * s;
        else if (mode == ORR_SAMPLES_ADD)
            out[m] += s;
        else
            out[m] = s;
    }
}

/* Static, with an exported wrapper below: Clang does not export a
 * multi-versioned function under its plain name. */
ORR_VECTOR_CLONES
static void plain_row(const orr_sample_poly *p, float a, float bdy, float cdy, float dx0, int m0, int m1, float *out,
                      orr_sample_mode mode, float scale)
{
    switch (mode) {
    case ORR_SAMPLES_SET: plain_loop(p, a, bdy, cdy, dx0, m0, m1, out, ORR_SAMPLES_SET, scale); break;
    case ORR_SAMPLES_ADD: plain_loop(p, a, bdy, cdy, dx0, m0, m1, out, ORR_SAMPLES_ADD, scale); break;
    case ORR_SAMPLES_DRAW: plain_loop(p, a, bdy, cdy, dx0, m0, m1, out, ORR_SAMPLES_DRAW, scale); break;
    }
}

void orr_sample_row_plain(const orr_sample_poly *p, float a, float bdy, float cdy, float dx0, int m0, int m1,
                          float *out, orr_sample_mode mode, float scale)
{
    plain_row(p, a, bdy, cdy, dx0, m0, m1, out, mode, scale);
}

#ifdef HAVE_VECTOR_ROWS
/* AVX-512: sixteen samples at once. The 32 pieces' values of coefficient d
 * sit in lo[d] (pieces 0-15) and hi[d] (16-31), and _mm512_permutex2var_ps
 * picks each lane's from the two. */
typedef struct poly512 {
    __m512 lo[DEGREE + 1], hi[DEGREE + 1];
} poly512;

__attribute__((target("avx512f"))) static ORR_ALWAYS_INLINE void poly512_load(poly512 *q, const orr_sample_poly *p)
{
    for (int d = 0; d <= DEGREE; d++) {
        q->lo[d] = _mm512_load_ps(p->c[d]);
        q->hi[d] = _mm512_load_ps(p->c[d] + 16);
    }
}

/* The samples at dx = dx0 + mf, mf holding sixteen consecutive columns (as
 * floats, exact below 2^24): sample_at's operations and values lane-wise,
 * in as few instructions as give them, as the loop is bound by their
 * number. */
__attribute__((target("avx512f"))) static ORR_ALWAYS_INLINE __m512 samples16(const poly512 *q, __m512 va, __m512 vbdy,
                                                                            __m512 vcdy, __m512 vdx0, __m512 mf)
{
    const __m512 dx = _mm512_add_ps(vdx0, mf);
    const __m512 t = _mm512_mul_ps(_mm512_add_ps(_mm512_mul_ps(_mm512_add_ps(_mm512_mul_ps(va, dx), vbdy), dx), vcdy),
                                   _mm512_set1_ps(ORR_KERNEL_POLY_T));
    /* orr_kernel_poly_piece: ti = min(trunc(t), 30) (a NaN t gives 30, as
     * there), x = t - ti, and the piece ti + 1, less one below t = 0.25
     * (below t = 1, ti is 0: pieces 0 and 1). */
    const __m512i ti = _mm512_cvttps_epi32(_mm512_min_ps(t, _mm512_set1_ps((float)ORR_KERNEL_POLY_LAST)));
    const __m512 x = _mm512_sub_ps(t, _mm512_cvtepi32_ps(ti));
    const __m512i one = _mm512_set1_epi32(1), next = _mm512_add_epi32(ti, one);
    const __mmask16 below_q = _mm512_cmp_ps_mask(t, _mm512_set1_ps(0.25f), _CMP_LT_OQ);
    const __m512i piece = _mm512_mask_sub_epi32(next, below_q, next, one);
    __m512 s = _mm512_permutex2var_ps(q->lo[DEGREE], piece, q->hi[DEGREE]);
    for (int d = DEGREE - 1; d >= 0; d--)
        s = _mm512_add_ps(_mm512_mul_ps(s, x), _mm512_permutex2var_ps(q->lo[d], piece, q->hi[d]));
    const __mmask16 inside = _mm512_cmp_ps_mask(t, _mm512_set1_ps(T_EDGE), _CMP_LT_OQ);
    return _mm512_maskz_mov_ps(inside, s);
}

/* Columns m .. m + 15 as floats. */
__attribute__((target("avx512f"))) static ORR_ALWAYS_INLINE __m512 columns16(int m)
{
    const __m512i lanes = _mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
    return _mm512_cvtepi32_ps(_mm512_add_epi32(_mm512_set1_epi32(m), lanes));
}

/* The lanes of the 16 samples from m that fall in [m0, m1). */
static inline __mmask16 live16(int m, int m0, int m1)
{
    const int from = m0 > m ? m0 - m : 0, to = m1 - m < 16 ? m1 - m : 16;
    return to > from ? (__mmask16)(((1u << to) - 1u) & ~((1u << from) - 1u)) : (__mmask16)0;
}

/* Sixteen samples an iteration; the last, partial one masked. */
__attribute__((target("avx512f"))) static void row_avx512(const orr_sample_poly *p, float a, float bdy, float cdy,
                                                          float dx0, int m0, int m1, float *out,
                                                          orr_sample_mode mode, float scale)
{
    poly512 q;
    poly512_load(&q, p);
    const __m512 va = _mm512_set1_ps(a), vbdy = _mm512_set1_ps(bdy), vcdy = _mm512_set1_ps(cdy);
    const __m512 vdx0 = _mm512_set1_ps(dx0), vscale = _mm512_set1_ps(scale);
    const __m512 step = _mm512_set1_ps(16.0f);
    __m512 mf = columns16(m0);
    for (int m = m0; m < m1; m += 16, mf = _mm512_add_ps(mf, step)) {
        const __mmask16 live = live16(m, m0, m1);
        const __m512 s = samples16(&q, va, vbdy, vcdy, vdx0, mf);
        if (mode == ORR_SAMPLES_SET) {
            _mm512_mask_storeu_ps(out + m, live, s);
            continue;
        }
        const __m512 o = _mm512_maskz_loadu_ps(live, out + m);
        const __m512 add = mode == ORR_SAMPLES_DRAW ? _mm512_mul_ps(vscale, s) : s;
        _mm512_mask_storeu_ps(out + m, live, _mm512_add_ps(o, add));
    }
}

/* SPAN_GROUP spans at once, over the union of their columns: the spans'
 * samples are independent chains of operations, which the core overlaps.
 * A lane outside its span is computed but neither read nor written. */
#define SPAN_GROUP 4
__attribute__((target("avx512f"))) static void spans_avx512(const orr_sample_poly *p, float a, float dx0,
                                                            const orr_sample_span *sp, int n, float scale)
{
    poly512 q;
    poly512_load(&q, p);
    const __m512 va = _mm512_set1_ps(a), vdx0 = _mm512_set1_ps(dx0), vscale = _mm512_set1_ps(scale);
    const __m512 step = _mm512_set1_ps(16.0f);
    int g = 0;
    for (; g + SPAN_GROUP <= n; g += SPAN_GROUP) {
        const orr_sample_span *s = sp + g;
        __m512 vbdy[SPAN_GROUP], vcdy[SPAN_GROUP];
        int lo = s[0].m0, hi = s[0].m1;
        for (int r = 0; r < SPAN_GROUP; r++) {
            vbdy[r] = _mm512_set1_ps(s[r].bdy);
            vcdy[r] = _mm512_set1_ps(s[r].cdy);
            lo = s[r].m0 < lo ? s[r].m0 : lo;
            hi = s[r].m1 > hi ? s[r].m1 : hi;
        }
        __m512 mf = columns16(lo);
        for (int m = lo; m < hi; m += 16, mf = _mm512_add_ps(mf, step))
            for (int r = 0; r < SPAN_GROUP; r++) {
                const __mmask16 live = live16(m, s[r].m0, s[r].m1);
                const __m512 v = samples16(&q, va, vbdy[r], vcdy[r], vdx0, mf);
                const __m512 o = _mm512_maskz_loadu_ps(live, s[r].out + m);
                _mm512_mask_storeu_ps(s[r].out + m, live, _mm512_add_ps(o, _mm512_mul_ps(vscale, v)));
            }
    }
    for (; g < n; g++)
        row_avx512(p, a, sp[g].bdy, sp[g].cdy, dx0, sp[g].m0, sp[g].m1, sp[g].out, ORR_SAMPLES_DRAW, scale);
}

/* Eight samples with AVX2, at columns m .. m + 7: each lane's coefficient
 * from four registers, by one permute of each and two blends on bits 3 and
 * 4 of the piece. */
__attribute__((target("avx2"))) static ORR_ALWAYS_INLINE __m256 samples8(const orr_sample_poly *p, __m256 va,
                                                                        __m256 vbdy, __m256 vcdy, __m256 vdx0, int m)
{
    const __m256i lanes = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
    const __m256i last = _mm256_set1_epi32(ORR_KERNEL_POLY_LAST), one = _mm256_set1_epi32(1);
    const __m256 vt = _mm256_set1_ps(ORR_KERNEL_POLY_T);
    const __m256 dx = _mm256_add_ps(vdx0, _mm256_cvtepi32_ps(_mm256_add_epi32(_mm256_set1_epi32(m), lanes)));
    const __m256 t = _mm256_mul_ps(_mm256_add_ps(_mm256_mul_ps(_mm256_add_ps(_mm256_mul_ps(va, dx), vbdy), dx), vcdy), vt);
    const __m256i below_last = _mm256_castps_si256(_mm256_cmp_ps(t, _mm256_set1_ps((float)ORR_KERNEL_POLY_LAST), _CMP_LT_OQ));
    const __m256i ti = _mm256_blendv_epi8(last, _mm256_cvttps_epi32(t), below_last);
    const __m256 x = _mm256_sub_ps(t, _mm256_cvtepi32_ps(ti));
    const __m256i below_1 = _mm256_castps_si256(_mm256_cmp_ps(t, _mm256_set1_ps(1.0f), _CMP_LT_OQ));
    const __m256i below_q = _mm256_castps_si256(_mm256_cmp_ps(t, _mm256_set1_ps(0.25f), _CMP_LT_OQ));
    const __m256i centre = _mm256_andnot_si256(below_q, one);
    const __m256i piece = _mm256_blendv_epi8(_mm256_add_epi32(ti, one), centre, below_1);
    const __m256 bit3 = _mm256_castsi256_ps(_mm256_slli_epi32(piece, 28));
    const __m256 bit4 = _mm256_castsi256_ps(_mm256_slli_epi32(piece, 27));
    __m256 c[DEGREE + 1];
    for (int d = 0; d <= DEGREE; d++) {
        const float *row = p->c[d];
        const __m256 r0 = _mm256_permutevar8x32_ps(_mm256_load_ps(row), piece);
        const __m256 r1 = _mm256_permutevar8x32_ps(_mm256_load_ps(row + 8), piece);
        const __m256 r2 = _mm256_permutevar8x32_ps(_mm256_load_ps(row + 16), piece);
        const __m256 r3 = _mm256_permutevar8x32_ps(_mm256_load_ps(row + 24), piece);
        c[d] = _mm256_blendv_ps(_mm256_blendv_ps(r0, r1, bit3), _mm256_blendv_ps(r2, r3, bit3), bit4);
    }
    __m256 s = c[DEGREE];
    for (int d = DEGREE - 1; d >= 0; d--)
        s = _mm256_add_ps(_mm256_mul_ps(s, x), c[d]);
    return _mm256_and_ps(s, _mm256_cmp_ps(t, _mm256_set1_ps(T_EDGE), _CMP_LT_OQ));
}

/* Eight samples an iteration; the last, short one under a mask (the
 * kernels of 2 to 10 pixels have rows of a few to a few tens of samples,
 * and a plain tail of up to seven cost as much as the vector part). A
 * masked load or store touches no column outside the row. */
__attribute__((target("avx2"))) static void row_avx2(const orr_sample_poly *p, float a, float bdy, float cdy,
                                                     float dx0, int m0, int m1, float *out, orr_sample_mode mode,
                                                     float scale)
{
    const __m256 va = _mm256_set1_ps(a), vbdy = _mm256_set1_ps(bdy), vcdy = _mm256_set1_ps(cdy);
    const __m256 vdx0 = _mm256_set1_ps(dx0), vscale = _mm256_set1_ps(scale);
    int m = m0;
    for (; m + 8 <= m1; m += 8) {
        const __m256 s = samples8(p, va, vbdy, vcdy, vdx0, m);
        if (mode == ORR_SAMPLES_SET) {
            _mm256_storeu_ps(out + m, s);
            continue;
        }
        const __m256 add = mode == ORR_SAMPLES_DRAW ? _mm256_mul_ps(vscale, s) : s;
        _mm256_storeu_ps(out + m, _mm256_add_ps(_mm256_loadu_ps(out + m), add));
    }
    if (m == m1)
        return;
    const __m256i live = _mm256_cmpgt_epi32(_mm256_set1_epi32(m1 - m), _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7));
    const __m256 s = samples8(p, va, vbdy, vcdy, vdx0, m);
    const __m256 add = mode == ORR_SAMPLES_DRAW ? _mm256_mul_ps(vscale, s) : s;
    _mm256_maskstore_ps(out + m, live, mode == ORR_SAMPLES_SET ? s : _mm256_add_ps(_mm256_maskload_ps(out + m, live), add));
}

orr_sample_rows orr_sample_rows_best(void)
{
    return __builtin_cpu_supports("avx512f") ? ORR_ROWS_AVX512
           : __builtin_cpu_supports("avx2")  ? ORR_ROWS_AVX2
                                             : ORR_ROWS_PLAIN;
}
#else
orr_sample_rows orr_sample_rows_best(void)
{
    return ORR_ROWS_PLAIN;
}
#endif

void orr_sample_row_with(orr_sample_rows rows, const orr_sample_poly *p, float a, float bdy, float cdy, float dx0,
                         int m0, int m1, float *out, orr_sample_mode mode, float scale)
{
#ifdef HAVE_VECTOR_ROWS
    if (rows == ORR_ROWS_AVX512) {
        row_avx512(p, a, bdy, cdy, dx0, m0, m1, out, mode, scale);
        return;
    }
    if (rows == ORR_ROWS_AVX2) {
        row_avx2(p, a, bdy, cdy, dx0, m0, m1, out, mode, scale);
        return;
    }
#endif
    (void)rows;
    orr_sample_row_plain(p, a, bdy, cdy, dx0, m0, m1, out, mode, scale);
}

void orr_sample_row(const orr_sample_poly *p, float a, float bdy, float cdy, float dx0, int m0, int m1,
                    float *out, orr_sample_mode mode, float scale)
{
    orr_sample_row_with(orr_sample_rows_best(), p, a, bdy, cdy, dx0, m0, m1, out, mode, scale);
}

void orr_sample_spans_draw(const orr_sample_poly *p, float a, float dx0, const orr_sample_span *spans, int n,
                           float scale)
{
#ifdef HAVE_VECTOR_ROWS
    if (orr_sample_rows_best() == ORR_ROWS_AVX512) {
        spans_avx512(p, a, dx0, spans, n, scale);
        return;
    }
#endif
    for (int r = 0; r < n; r++)
        orr_sample_row(p, a, spans[r].bdy, spans[r].cdy, dx0, spans[r].m0, spans[r].m1, spans[r].out,
                       ORR_SAMPLES_DRAW, scale);
}
