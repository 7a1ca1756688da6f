/* Codes of values and of their sRGB encoding (core/srgb_code.h). */
#include "core/srgb_code.h"

#include <math.h>
#include <pthread.h>
#include <string.h>

#include "core/colourimetry.h"

void orr_codes_of(const float *v, size_t n, int bits, uint16_t *codes)
{
    unsigned max = bits == 8 ? 255u : 65535u;
    for (size_t i = 0; i < n; i++)
        codes[i] = (uint16_t)orr_code_of(v[i], max);
}

/* The code a linear value gets by the formula the table replaces. */
static unsigned direct_code(float x, unsigned max) { return orr_code_of((float)orr_srgb_encode(x), max); }

/* The code is a non-decreasing function of the float x: checked over every
 * float from 0 to just above 1 when this was written (the encoded float
 * dips once, by 14 units in its last place where the curve's linear part
 * meets its power law at 0.0031308, inside one code; test_srgb_code checks
 * the table against the formula). So it is the number of codes q >= 1 whose
 * threshold, the least float with code >= q, is <= x. A guess from an
 * interpolated coarse table of the curve, then a step or two against the
 * thresholds, finds that number exactly. */
enum {
    LO_EXPONENT = 127 - 24,    /* the guess's table starts at 2^-24, below either first threshold */
    NODE_SHIFT = 16,           /* 2^7 nodes an octave: the guess within a fraction of a code */
    OCTAVES = 24,
    NODES = (OCTAVES << (23 - NODE_SHIFT)) + 1,
    MAX16 = 65535,
};
#define LO_BITS ((uint32_t)LO_EXPONENT << 23)

typedef struct srgb_table {
    unsigned max;
    float threshold[MAX16 + 2]; /* [q]: the least float with code >= q, for q in [1, max]; [max + 1] = inf */
    float guess[NODES];         /* the encoded value times max at each node */
} srgb_table;

static srgb_table tables[2]; /* 8 and 16 bits */
static pthread_once_t table_once[2] = {PTHREAD_ONCE_INIT, PTHREAD_ONCE_INIT};

static float float_of_bits(uint32_t b)
{
    float x;
    memcpy(&x, &b, sizeof x);
    return x;
}

/* The least float whose code is >= q, from the inverse curve's guess
 * (within a few floats of it) stepped to the exact boundary. */
static float threshold_of(unsigned q, unsigned max)
{
    float x = (float)orr_srgb_decode((q - 0.5) / max);
    if (direct_code(x, max) >= q) {
        for (float below = nextafterf(x, 0); direct_code(below, max) >= q; below = nextafterf(below, 0))
            x = below;
    } else {
        while (direct_code(x, max) < q)
            x = nextafterf(x, INFINITY);
    }
    return x;
}

static void build(srgb_table *t, unsigned max)
{
    t->max = max;
    t->threshold[0] = 0;
    for (unsigned q = 1; q <= max; q++)
        t->threshold[q] = threshold_of(q, max);
    t->threshold[max + 1] = INFINITY;
    for (int k = 0; k < NODES; k++)
        t->guess[k] = (float)(orr_srgb_encode(float_of_bits(LO_BITS + ((uint32_t)k << NODE_SHIFT))) * max);
}

static void build8(void) { build(&tables[0], 255); }
static void build16(void) { build(&tables[1], MAX16); }

static const srgb_table *table_for(int bits)
{
    if (bits == 8) {
        pthread_once(&table_once[0], build8);
        return &tables[0];
    }
    pthread_once(&table_once[1], build16);
    return &tables[1];
}

static unsigned table_code(const srgb_table *t, float x)
{
    const float *th = t->threshold;
    if (!(x >= th[1])) /* NaN, x <= 0 and the darkest values */
        return 0;
    if (x >= th[t->max])
        return t->max;
    uint32_t b;
    memcpy(&b, &x, sizeof b);
    b -= LO_BITS; /* x >= th[1] > 2^-24 */
    uint32_t k = b >> NODE_SHIFT;
    float frac = (float)(b & ((1u << NODE_SHIFT) - 1)) * (1.0f / (1u << NODE_SHIFT));
    float guess = t->guess[k] + frac * (t->guess[k + 1] - t->guess[k]);
    unsigned q = (unsigned)(guess + 0.5f);
    q = q < 1 ? 1 : q > t->max ? t->max : q;
    while (x >= th[q + 1])
        q++;
    while (x < th[q]) /* stops at 1: x >= th[1] */
        q--;
    return q;
}

void orr_srgb_codes_of(const float *linear, size_t n, int bits, uint16_t *codes)
{
    const srgb_table *t = table_for(bits);
    for (size_t i = 0; i < n; i++)
        codes[i] = (uint16_t)table_code(t, linear[i]);
}
