#include "render/map_alpha.h"

#include <math.h>
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

/* The half-width of the map's outline along the pixel line y (corners'
 * height), in pixels; negative where the line misses it. */
static double outline_half_width(const orr_projection *p, double y)
{
    const double v = y - p->cy;
    if (p->settings.kind == ORR_PROJ_DOME) {
        const double r2 = p->half_w * p->half_w - v * v;
        return r2 >= 0 ? sqrt(r2) : -1;
    }
    const double t = 1 - (v / p->half_h) * (v / p->half_h);
    return t >= 0 ? p->half_w * sqrt(t) : -1;
}

void orr_map_row_coverage(const orr_projection *p, int j, float *out)
{
    if (!orr_projection_traits_of(p->settings.kind).elliptic_map) {
        for (int i = 0; i < p->width; i++)
            out[i] = 1.0f; /* every point on the map: four corners in */
        return;
    }
    /* Pixels whose corners are inside both lines' spans by a margin (far
     * above the rounding of orr_projection_point_in_map's test, whose
     * answers it thus repeats) have all four corners in: coverage 1;
     * those beyond both spans none: 0; only the rest, along the outline,
     * are sampled. */
    const double margin = 1e-6 * (p->half_w + p->half_h + 1);
    const double w0 = outline_half_width(p, j), w1 = outline_half_width(p, j + 1.0);
    const double in = fmin(w0, w1) - margin, out_from = fmax(w0, w1) + margin;
    for (int i = 0; i < p->width; i++) {
        const double x0 = i - p->cx, x1 = x0 + 1;
        if (in > 0 && x0 >= -in && x1 <= in)
            out[i] = 1.0f;
        else if (fmax(w0, w1) < 0 || x1 <= -out_from || x0 >= out_from)
            out[i] = 0.0f;
        else
            out[i] = orr_map_pixel_coverage(p, i, j);
    }
}

void orr_map_alpha_fill(const orr_projection *p, float *alpha)
{
#pragma omp parallel for schedule(static)
    for (int j = 0; j < p->height; j++)
        orr_map_row_coverage(p, j, alpha + (size_t)j * (size_t)p->width);
}

orr_status orr_map_rgba(const orr_projection *p, const float *rgb, float **rgba, orr_error *err)
{
    size_t npix = (size_t)p->width * (size_t)p->height;
    float *out = orr_malloc(npix * 4 * sizeof *out, "picture with alpha", err);
    float *row = out ? orr_malloc((size_t)p->width * sizeof *row, "picture with alpha", err) : NULL;
    if (!row) {
        free(out);
        return ORR_ERR_NOMEM;
    }
    for (int j = 0; j < p->height; j++) {
        orr_map_row_coverage(p, j, row);
        for (int i = 0; i < p->width; i++) {
            size_t at = (size_t)j * (size_t)p->width + (size_t)i;
            float alpha = row[i];
            for (int c = 0; c < 3; c++) /* not premultiplied (PNG's alpha): the colour as the picture has it */
                out[4 * at + (size_t)c] = alpha > 0 ? rgb[3 * at + (size_t)c] : 0.0f;
            out[4 * at + 3] = alpha;
        }
    }
    free(row);
    *rgba = out;
    return ORR_OK;
}
