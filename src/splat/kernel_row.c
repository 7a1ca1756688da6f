#include "splat/kernel_row.h"

#include "core/simd.h"

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__)) && !defined(ORR_NO_CLONES)
#define HAVE_AVX512_ROW 1
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
static inline float sample_at(const orr_sample_poly *p, float t)
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
static inline float sample_t(float a, float bdy, float cdy, float dx)
{
    return ((a * dx + bdy) * dx + cdy) * ORR_KERNEL_POLY_T;
}

void orr_sample_row_plain(const orr_sample_poly *p, float a, float bdy, float cdy, float dx0, int m0, int m1,
                          float *out, orr_sample_mode mode, float scale)
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

#ifdef HAVE_AVX512_ROW
/* Sixteen samples an iteration; the last, partial one masked. The 32
 * pieces' values of coefficient d sit in lo[d] (pieces 0-15) and hi[d]
 * (16-31), and _mm512_permutex2var_ps picks each lane's from the two. */
__attribute__((target("avx512f"))) static void row_avx512(const orr_sample_poly *p, float a, float bdy, float cdy,
                                                          float dx0, int m0, int m1, float *out,
                                                          orr_sample_mode mode, float scale)
{
    __m512 lo[DEGREE + 1], hi[DEGREE + 1];
    for (int d = 0; d <= DEGREE; d++) {
        lo[d] = _mm512_load_ps(p->c[d]);
        hi[d] = _mm512_load_ps(p->c[d] + 16);
    }
    const __m512 va = _mm512_set1_ps(a), vbdy = _mm512_set1_ps(bdy), vcdy = _mm512_set1_ps(cdy);
    const __m512 vt = _mm512_set1_ps(ORR_KERNEL_POLY_T), vdx0 = _mm512_set1_ps(dx0), vscale = _mm512_set1_ps(scale);
    const __m512i lanes = _mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
    const __m512i last = _mm512_set1_epi32(ORR_KERNEL_POLY_LAST), one = _mm512_set1_epi32(1);
    for (int m = m0; m < m1; m += 16) {
        const __mmask16 live = m1 - m >= 16 ? (__mmask16)0xffff : (__mmask16)((1u << (m1 - m)) - 1u);
        const __m512 dx = _mm512_add_ps(vdx0, _mm512_cvtepi32_ps(_mm512_add_epi32(_mm512_set1_epi32(m), lanes)));
        const __m512 t = _mm512_mul_ps(_mm512_add_ps(_mm512_mul_ps(_mm512_add_ps(_mm512_mul_ps(va, dx), vbdy), dx), vcdy), vt);
        /* orr_kernel_poly_piece, lane-wise: t < 30 truncates (t >= 0 up to
         * rounding, where truncation and the scalar (int) agree). */
        const __mmask16 below_last = _mm512_cmp_ps_mask(t, _mm512_set1_ps((float)ORR_KERNEL_POLY_LAST), _CMP_LT_OQ);
        const __m512i ti = _mm512_mask_blend_epi32(below_last, last, _mm512_cvttps_epi32(t));
        const __m512 x = _mm512_sub_ps(t, _mm512_cvtepi32_ps(ti));
        const __mmask16 below_1 = _mm512_cmp_ps_mask(t, _mm512_set1_ps(1.0f), _CMP_LT_OQ);
        const __mmask16 below_q = _mm512_cmp_ps_mask(t, _mm512_set1_ps(0.25f), _CMP_LT_OQ);
        const __m512i centre = _mm512_mask_blend_epi32(below_q, one, _mm512_setzero_si512());
        const __m512i piece = _mm512_mask_blend_epi32(below_1, _mm512_add_epi32(ti, one), centre);
        __m512 s = _mm512_permutex2var_ps(lo[DEGREE], piece, hi[DEGREE]);
        for (int d = DEGREE - 1; d >= 0; d--)
            s = _mm512_add_ps(_mm512_mul_ps(s, x), _mm512_permutex2var_ps(lo[d], piece, hi[d]));
        const __mmask16 inside = _mm512_cmp_ps_mask(t, _mm512_set1_ps(T_EDGE), _CMP_LT_OQ);
        s = _mm512_maskz_mov_ps(inside, s);
        if (mode == ORR_SAMPLES_SET) {
            _mm512_mask_storeu_ps(out + m, live, s);
            continue;
        }
        const __m512 o = _mm512_maskz_loadu_ps(live, out + m);
        const __m512 add = mode == ORR_SAMPLES_DRAW ? _mm512_mul_ps(vscale, s) : s;
        _mm512_mask_storeu_ps(out + m, live, _mm512_add_ps(o, add));
    }
}

int orr_sample_row_vector(void)
{
    return __builtin_cpu_supports("avx512f");
}
#else
int orr_sample_row_vector(void)
{
    return 0;
}
#endif

void orr_sample_row(const orr_sample_poly *p, float a, float bdy, float cdy, float dx0, int m0, int m1,
                    float *out, orr_sample_mode mode, float scale)
{
#ifdef HAVE_AVX512_ROW
    if (__builtin_cpu_supports("avx512f")) {
        row_avx512(p, a, bdy, cdy, dx0, m0, m1, out, mode, scale);
        return;
    }
#endif
    orr_sample_row_plain(p, a, bdy, cdy, dx0, m0, m1, out, mode, scale);
}
