#include "post/brightness.h"

#include <omp.h>
#include <stdio.h>
#include <stdlib.h>

/* Row j of every plane times inverse[i] per pixel: in double, then rounded
 * once, the value being the flux's own float divided by a measure known to
 * double precision. */
static void scale_row(orr_plane *planes, int n, int width, int j, const double *inverse)
{
    for (int k = 0; k < n; k++) {
        float *row = planes[k].data + (size_t)j * (size_t)width;
        for (int i = 0; i < width; i++)
            row[i] = (float)(row[i] * inverse[i]);
    }
}

/* Row j's inverse measures, each pixel's own (orr_pixel_measure_row
 * evaluates each distinct one once: a dome's sines are most of the cost). */
static void inverse_measures(const orr_projection *p, int j, double *inverse)
{
    orr_pixel_measure_row(p, j, inverse);
    for (int i = 0; i < p->width; i++)
        inverse[i] = 1.0 / inverse[i];
}

/* Without memory for a row of measures: pixel by pixel, the same values. */
static void pixel_by_pixel(const orr_projection *p, orr_plane *planes, int n)
{
    const int width = p->width, height = p->height;
#pragma omp parallel for schedule(static)
    for (int j = 0; j < height; j++)
        for (int i = 0; i < width; i++) {
            double inverse = 1.0 / orr_pixel_measure(p, i, j);
            size_t at = (size_t)j * (size_t)width + (size_t)i;
            for (int k = 0; k < n; k++)
                planes[k].data[at] = (float)(planes[k].data[at] * inverse);
        }
}

void orr_to_surface_brightness(const orr_projection *p, orr_plane *planes, int n)
{
    const int width = p->width, height = p->height;
    double *rows = malloc((size_t)omp_get_max_threads() * (size_t)width * sizeof *rows);
    if (!rows) {
        pixel_by_pixel(p, planes, n);
        return;
    }
#pragma omp parallel for schedule(dynamic, 8)
    for (int j = 0; j < height; j++) {
        int twin = orr_pixel_measure_twin_row(p, j);
        if (twin >= 0 && twin < j) /* done with its twin */
            continue;
        double *inverse = rows + (size_t)omp_get_thread_num() * (size_t)width;
        inverse_measures(p, j, inverse);
        scale_row(planes, n, width, j, inverse);
        if (twin >= 0)
            scale_row(planes, n, width, twin, inverse);
    }
    free(rows);
}

void orr_brightness_unit(const orr_projection *p, const char *weight_unit, const char *length_unit, char *out,
                         size_t size)
{
    const char *w = weight_unit ? weight_unit : "";
    const char *l = length_unit ? length_unit : "";
    /* FITS unit strings multiply by juxtaposition and divide by negative
     * powers ("solMass sr-1"): a "/" would divide everything after it. */
    if (p->settings.kind != ORR_PROJ_ORTHOGRAPHIC)
        snprintf(out, size, "%s%ssr-1", w, w[0] ? " " : "");
    else if (l[0])
        snprintf(out, size, "%s%s%s-2", w, w[0] ? " " : "", l);
    else
        snprintf(out, size, "%s", ""); /* per an unknown area: no unit can say it */
}
