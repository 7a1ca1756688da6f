/* A view's planes made ready for its files and its picture: the pixels off
 * a sky map blanked, and the planes graded into display RGB (the colour
 * synthesis of X, Y, Z planes, one plane in a tint, or one plane stretched
 * and colour-mapped). */
#ifndef ORR_POST_GRADE_H
#define ORR_POST_GRADE_H

#include "core/colourimetry.h"
#include "core/error.h"
#include "core/plane.h"
#include "core/srgb_code.h"
#include "frame/projection.h"
#include "post/colormap.h"
#include "post/colour.h"
#include "post/stretch.h"

/* Pixels outside a sky map hold no sky: NaN marks them blank in FITS (and
 * the stretch shows them black) in planes[0..nplanes), which have p's
 * size. Deposits never put weight there. Nothing for a flat projection. */
void orr_mask_outside_map(const orr_projection *p, orr_plane *planes, int nplanes);

/* How planes become a picture. */
typedef enum {
    ORR_GRADE_SYNTHESIS, /* X, Y, Z planes: their colour synthesis */
    ORR_GRADE_TINT,      /* one plane as luminance, drawn in one colour from a path of colours */
    ORR_GRADE_COLORMAP,  /* one plane stretched and colour-mapped */
} orr_grade_kind;

typedef struct orr_grade {
    orr_grade_kind kind;
    const orr_colour_synth *synth; /* synthesis and tint */
    const orr_colour_path *tint;   /* tint: the path, and the position along it */
    double tint_t;
    int linear;                    /* synthesis and tint: leave the values linear, else sRGB-encode them */
    const orr_stretch *stretch;    /* colour map: the stretch and the map */
    orr_colormap_kind colormap;
} orr_grade;

/* The picture of planes (X, Y, Z, or the one plane) as g says, width *
 * height * 3 values in [0, 1] into rgb (row 0 at the top); *white gets the
 * white level used (Y0 for synthesis and tint). */
orr_status orr_grade_picture(const orr_grade *g, const orr_plane *planes, float *rgb, double *white,
                             orr_error *err);

/* A picture graded a row at a time, so that it need never be held whole:
 * orr_grade_begin works out the white level (the percentile's pass over a
 * plane) once, then orr_graded_row gives any row, from any thread, the
 * values orr_grade_picture gives it. */
typedef struct orr_graded {
    orr_grade grade;
    const orr_plane *planes; /* borrowed: they must outlive the rows */
    double white;            /* the white level: Y0 for synthesis and tint */
    double unit[3];          /* tint: its colour at Y = 1 */
} orr_graded;

orr_status orr_grade_begin(const orr_grade *g, const orr_plane *planes, orr_graded *out, orr_error *err);

/* Row y of the picture: width * 3 values into rgb. */
void orr_graded_row(const orr_graded *gr, int y, float *rgb);

/* Row y of the picture as codes of `bits` (8 or 16), width * 3 of them:
 * the codes orr_code_of gives orr_graded_row's values (core/srgb_code.h),
 * made without the sRGB curve's pow. scratch holds width * 3 floats. */
void orr_graded_row_codes(const orr_graded *gr, int y, int bits, float *scratch, uint16_t *codes);

/* Every row, on every thread: width * height * 3 values into rgb. */
void orr_graded_picture(const orr_graded *gr, float *rgb);

#endif
