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

orr_status orr_grade_picture(const orr_grade *g, const orr_plane *planes, float *rgb, double *white,
                             orr_error *err)
{
    size_t npix = (size_t)planes[0].width * (size_t)planes[0].height;
    if (g->kind != ORR_GRADE_COLORMAP) {
        double xyz[3];
        orr_status st = ORR_OK;
        if (g->kind == ORR_GRADE_SYNTHESIS)
            st = orr_colour_synthesise(g->synth, &planes[0], &planes[1], &planes[2], rgb, white, err);
        else if (!(st = orr_colour_path_xyz(g->tint, g->tint_t, xyz, err)))
            st = orr_colour_synthesise_mono(g->synth, &planes[0], xyz, rgb, white, err);
        if (!st && !g->linear)
            orr_srgb_encode_buffer(rgb, npix * 3);
        return st;
    }
    float *t = orr_malloc(npix * sizeof(float), "stretched image", err);
    if (!t)
        return ORR_ERR_NOMEM;
    orr_status st = orr_stretch_apply(g->stretch, &planes[0], t, white, err);
    if (!st) {
#pragma omp parallel for schedule(static)
        for (size_t i = 0; i < npix; i++)
            orr_colormap_lookup(g->colormap, t[i], &rgb[3 * i]);
    }
    free(t);
    return st;
}
