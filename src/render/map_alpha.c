#include "render/map_alpha.h"

#include <stdlib.h>

/* Sample points per side of a pixel the outline crosses: its coverage in
 * steps of 1/256. */
#define COVERAGE_SAMPLES 16

float orr_map_pixel_coverage(const orr_projection *p, int i, int j)
{
    /* The outlines (a circle, an ellipse) are convex: a pixel whose four
     * corners agree is wholly inside or (but for a sliver under 1/(8 R) of
     * a pixel where the outline's extreme points poke through a side, far
     * below one sample) wholly outside. */
    int corners = orr_projection_point_in_map(p, i, j) + orr_projection_point_in_map(p, i + 1, j) +
                  orr_projection_point_in_map(p, i, j + 1) + orr_projection_point_in_map(p, i + 1, j + 1);
    if (corners == 0 || corners == 4)
        return corners ? 1.0f : 0.0f;
    int inside = 0;
    for (int t = 0; t < COVERAGE_SAMPLES; t++)
        for (int s = 0; s < COVERAGE_SAMPLES; s++)
            inside += orr_projection_point_in_map(p, i + (s + 0.5) / COVERAGE_SAMPLES,
                                                  j + (t + 0.5) / COVERAGE_SAMPLES);
    return (float)inside / (COVERAGE_SAMPLES * COVERAGE_SAMPLES);
}

void orr_map_alpha_fill(const orr_projection *p, float *alpha)
{
#pragma omp parallel for schedule(static)
    for (int j = 0; j < p->height; j++)
        for (int i = 0; i < p->width; i++)
            alpha[(size_t)j * (size_t)p->width + (size_t)i] = orr_map_pixel_coverage(p, i, j);
}

orr_status orr_map_rgba(const orr_projection *p, const float *rgb, float **rgba, orr_error *err)
{
    size_t npix = (size_t)p->width * (size_t)p->height;
    float *out = orr_malloc(npix * 4 * sizeof *out, "picture with alpha", err);
    if (!out)
        return ORR_ERR_NOMEM;
    for (int j = 0; j < p->height; j++)
        for (int i = 0; i < p->width; i++) {
            size_t at = (size_t)j * (size_t)p->width + (size_t)i;
            float alpha = orr_map_pixel_coverage(p, i, j);
            for (int c = 0; c < 3; c++) /* not premultiplied (PNG's alpha): the colour as the picture has it */
                out[4 * at + (size_t)c] = alpha > 0 ? rgb[3 * at + (size_t)c] : 0.0f;
            out[4 * at + 3] = alpha;
        }
    *rgba = out;
    return ORR_OK;
}
