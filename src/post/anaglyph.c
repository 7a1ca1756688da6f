#include "post/anaglyph.h"

#include <string.h>

/* E. Dubois, "A projection method to generate anaglyph stereo images",
 * Proc. IEEE ICASSP 2001, vol. 3, pp. 1661-1664; the red-cyan matrices are
 * those published on his web page (www.site.uottawa.ca/~edubois/anaglyph/,
 * "Least squares projection method", red-cyan), derived for typical
 * display primaries and filter transmissions. They act on linear RGB. */
const float orr_dubois_red_cyan_left[3][3] = {
    {0.437f, 0.449f, 0.164f},
    {-0.062f, -0.062f, -0.024f},
    {-0.048f, -0.050f, -0.017f},
};
const float orr_dubois_red_cyan_right[3][3] = {
    {-0.011f, -0.032f, -0.007f},
    {0.377f, 0.761f, 0.009f},
    {-0.026f, -0.093f, 1.234f},
};

/* Rec. 709 luminance of linear RGB (the primaries of sRGB). */
#define LUM_R 0.2126f
#define LUM_G 0.7152f
#define LUM_B 0.0722f

const orr_named orr_anaglyph_names[] = {
    {"grey", ORR_ANAGLYPH_GREY}, {"colour", ORR_ANAGLYPH_COLOUR}, {"dubois", ORR_ANAGLYPH_DUBOIS}, {NULL, 0}};

const char *orr_anaglyph_name(orr_anaglyph_kind kind) { return orr_named_name(orr_anaglyph_names, (int)kind); }

ORR_NAMED_PARSER(orr_anaglyph_from_name, orr_anaglyph_kind, orr_anaglyph_names)

static inline float clip01(float v) { return v < 0.0f ? 0.0f : v > 1.0f ? 1.0f : v; }

void orr_anaglyph_compose(orr_anaglyph_kind kind, const float *left, const float *right, size_t npix, float *out)
{
    for (size_t i = 0; i < npix; i++) {
        const float *l = &left[3 * i], *r = &right[3 * i];
        float o[3];
        if (kind == ORR_ANAGLYPH_GREY) {
            o[0] = LUM_R * l[0] + LUM_G * l[1] + LUM_B * l[2];
            o[1] = o[2] = LUM_R * r[0] + LUM_G * r[1] + LUM_B * r[2];
        } else if (kind == ORR_ANAGLYPH_COLOUR) {
            o[0] = l[0];
            o[1] = r[1];
            o[2] = r[2];
        } else {
            const float(*L)[3] = orr_dubois_red_cyan_left, (*R)[3] = orr_dubois_red_cyan_right;
            for (int c = 0; c < 3; c++)
                o[c] = L[c][0] * l[0] + L[c][1] * l[1] + L[c][2] * l[2] + R[c][0] * r[0] + R[c][1] * r[1] +
                       R[c][2] * r[2];
        }
        /* Written after both inputs are read, so out may alias either. */
        for (int c = 0; c < 3; c++)
            out[3 * i + c] = clip01(o[c]);
    }
}
