/* Blanking off the map and grading (post/grade.h). */
#include "post/grade.h"

#include <math.h>
#include <stdlib.h>

void orr_mask_outside_map(const orr_projection *p, orr_plane *planes, int nplanes)
{
    if (!orr_projection_is_sky(p))
        return;
    /* A row's pixels on the map are one run about the centre column (the
     * outline is an ellipse, a circle or the whole image): its ends are
     * found by bisection with the projection's own test, and only the
     * pixels outside are visited. */
    const int W = p->width, centre = (int)lround(p->cx - 0.5);
    for (int j = 0; j < p->height; j++) {
        int first = W, last = -1; /* the run [first, last], empty when last < first */
        if (centre >= 0 && centre < W && orr_projection_pixel_in_map(p, centre, j)) {
            int lo = 0, hi = centre; /* the first inside is in [lo, hi] */
            while (lo < hi) {
                int mid = lo + (hi - lo) / 2;
                if (orr_projection_pixel_in_map(p, mid, j))
                    hi = mid;
                else
                    lo = mid + 1;
            }
            first = lo;
            lo = centre, hi = W - 1; /* the last inside is in [lo, hi] */
            while (lo < hi) {
                int mid = hi - (hi - lo) / 2;
                if (orr_projection_pixel_in_map(p, mid, j))
                    lo = mid;
                else
                    hi = mid - 1;
            }
            last = lo;
        }
        const int left_end = first < W ? first : W, right_start = last + 1 > left_end ? last + 1 : left_end;
        for (int k = 0; k < nplanes; k++) {
            float *row = planes[k].data + (size_t)j * (size_t)W;
            for (int i = 0; i < left_end; i++)
                row[i] = NAN;
            for (int i = right_start; i < W; i++)
                row[i] = NAN;
        }
    }
}

orr_status orr_grade_begin(const orr_grade *g, const orr_plane *planes, orr_graded *out, orr_error *err)
{
    *out = (orr_graded){.grade = *g, .planes = planes};
    orr_status st = ORR_OK;
    double xyz[3];
    switch (g->kind) {
    case ORR_GRADE_SYNTHESIS:
        if (planes[0].width != planes[1].width || planes[0].height != planes[1].height ||
            planes[0].width != planes[2].width || planes[0].height != planes[2].height)
            return orr_fail(err, ORR_ERR_USAGE, "colour: planes X %dx%d, Y %dx%d, Z %dx%d differ in size",
                            planes[0].width, planes[0].height, planes[1].width, planes[1].height, planes[2].width,
                            planes[2].height);
        return orr_colour_synth_y0(g->synth, &planes[1], &out->white, err);
    case ORR_GRADE_TINT:
        if (!(st = orr_colour_path_xyz(g->tint, g->tint_t, xyz, err)) &&
            !(st = orr_colour_tint_unit(xyz, out->unit, err)))
            st = orr_colour_synth_y0(g->synth, &planes[0], &out->white, err);
        return st;
    case ORR_GRADE_COLORMAP:
        return orr_stretch_white(g->stretch, &planes[0], &out->white, err);
    }
    return orr_fail(err, ORR_ERR_INTERNAL, "unknown grade %d", (int)g->kind);
}

/* Row y's values before any sRGB encoding; 1 when they are linear and want
 * it, 0 when they are display values already (a colour map's, or
 * grade.linear). */
static int graded_values(const orr_graded *gr, int y, float *rgb)
{
    const orr_grade *g = &gr->grade;
    const size_t w = (size_t)gr->planes[0].width, at = (size_t)y * w;
    switch (g->kind) {
    case ORR_GRADE_SYNTHESIS:
        orr_colour_synthesise_span(g->synth, gr->white, gr->planes[0].data + at, gr->planes[1].data + at,
                                   gr->planes[2].data + at, w, rgb);
        break;
    case ORR_GRADE_TINT:
        orr_colour_synthesise_mono_span(g->synth, gr->white, gr->unit, gr->planes[0].data + at, w, rgb);
        break;
    case ORR_GRADE_COLORMAP: {
        /* The stretched values go into the row's last third, and the colours
         * are written from the front: pixel i's three values end at 3 i + 2,
         * before the stretched value of pixel i + 1 at 2 w + i + 1, so none
         * is overwritten before it is read. */
        float *t = rgb + 2 * w;
        orr_stretch_span(g->stretch, gr->white, gr->planes[0].data + at, w, t);
        for (size_t i = 0; i < w; i++)
            orr_colormap_lookup(g->colormap, t[i], &rgb[3 * i]);
        return 0; /* colour maps are sRGB already */
    }
    }
    return !g->linear;
}

void orr_graded_row(const orr_graded *gr, int y, float *rgb)
{
    if (graded_values(gr, y, rgb))
        for (size_t i = 0; i < 3 * (size_t)gr->planes[0].width; i++)
            rgb[i] = (float)orr_srgb_encode(rgb[i]);
}

void orr_graded_row_codes(const orr_graded *gr, int y, int bits, float *scratch, uint16_t *codes)
{
    size_t n = 3 * (size_t)gr->planes[0].width;
    if (graded_values(gr, y, scratch))
        orr_srgb_codes_of(scratch, n, bits, codes);
    else
        orr_codes_of(scratch, n, bits, codes);
}

void orr_graded_picture(const orr_graded *gr, float *rgb)
{
    const size_t w = (size_t)gr->planes[0].width;
#pragma omp parallel for schedule(static)
    for (int j = 0; j < gr->planes[0].height; j++)
        orr_graded_row(gr, j, rgb + 3 * (size_t)j * w);
}

orr_status orr_grade_picture(const orr_grade *g, const orr_plane *planes, float *rgb, double *white,
                             orr_error *err)
{
    orr_graded gr;
    orr_status st = orr_grade_begin(g, planes, &gr, err);
    if (st)
        return st;
    *white = gr.white;
    orr_graded_picture(&gr, rgb);
    return ORR_OK;
}
