/* Red-cyan anaglyphs: one picture holding a stereo pair, for glasses with a
 * red filter over the left eye and a cyan one over the right. The inputs
 * and the output are linear RGB (before the transfer curve), interleaved,
 * and the output is clipped to [0, 1]. docs/stereo.md. */
#ifndef ORR_POST_ANAGLYPH_H
#define ORR_POST_ANAGLYPH_H

#include <stddef.h>

#include "core/names.h"

typedef enum {
    ORR_ANAGLYPH_GREY,   /* luminance of the left eye -> red, of the right -> green and blue */
    ORR_ANAGLYPH_COLOUR, /* red from the left eye, green and blue from the right */
    ORR_ANAGLYPH_DUBOIS, /* Dubois's least-squares red-cyan projection (the default) */
} orr_anaglyph_kind;

/* Dubois's red-cyan matrices: output RGB = L * left RGB + R * right RGB
 * (rows are output channels). */
extern const float orr_dubois_red_cyan_left[3][3];
extern const float orr_dubois_red_cyan_right[3][3];

extern const orr_named orr_anaglyph_names[];
const char *orr_anaglyph_name(orr_anaglyph_kind kind);
/* 1 and *kind set when name is grey, colour or dubois; 0 otherwise. */
int orr_anaglyph_from_name(const char *name, orr_anaglyph_kind *kind);

/* out (npix * 3 values) from left and right (npix * 3 each). out may be
 * either input. */
void orr_anaglyph_compose(orr_anaglyph_kind kind, const float *left, const float *right, size_t npix, float *out);

#endif
