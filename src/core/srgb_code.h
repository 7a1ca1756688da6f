/* Pixel values to integer codes (8 or 16 bits) as a PNG stores them, and
 * linear values straight to the codes of their sRGB encoding without the
 * transfer curve's pow: each code's threshold is tabulated once, worked
 * out with the very formula it replaces, so the codes are the same by
 * construction (docs/output.md#png, docs/performance.md). */
#ifndef ORR_CORE_SRGB_CODE_H
#define ORR_CORE_SRGB_CODE_H

#include <stddef.h>
#include <stdint.h>

/* The code of v in [0, 1] with max = 2^bits - 1: clipped to [0, 1] (NaN
 * to 0) and rounded to the nearest code, floor(v * max + 0.5) in double so
 * that 16-bit codes round exactly as the formula says. Without branches,
 * so that loops over it vectorise: 1 gives max + 0.5, which truncates to
 * max. */
static inline unsigned orr_code_of(float v, unsigned max)
{
    float c = v > 0 ? v : 0.0f;
    c = c < 1 ? c : 1.0f;
    return (unsigned)((double)c * max + 0.5);
}

/* n values to codes of `bits` (8 or 16). */
void orr_codes_of(const float *v, size_t n, int bits, uint16_t *codes);

/* n linear values to the codes of their sRGB encoding: for each value x,
 * codes[i] = orr_code_of((float)orr_srgb_encode(x), 2^bits - 1), the same
 * code for every float x (NaN and x <= 0 give 0), bits 8 or 16. */
void orr_srgb_codes_of(const float *linear, size_t n, int bits, uint16_t *codes);

#endif
