#include "post/brightness.h"

#include <stdio.h>

void orr_to_surface_brightness(const orr_projection *p, orr_plane *planes, int n)
{
    const int width = p->width, height = p->height;
#pragma omp parallel for schedule(static)
    for (int j = 0; j < height; j++) {
        for (int i = 0; i < width; i++) {
            /* In double, then rounded once: the value is the flux's own
             * float divided by a measure known to double precision. */
            double inverse = 1.0 / orr_pixel_measure(p, i, j);
            size_t at = (size_t)j * (size_t)width + (size_t)i;
            for (int k = 0; k < n; k++)
                planes[k].data[at] = (float)(planes[k].data[at] * inverse);
        }
    }
}

void orr_brightness_unit(const orr_projection *p, const char *weight_unit, const char *length_unit, char *out,
                         size_t size)
{
    const char *w = weight_unit ? weight_unit : "";
    const char *l = length_unit ? length_unit : "";
    /* FITS unit strings multiply by juxtaposition and divide by negative
     * powers ("solMass sr-1"): a "/" would divide everything after it. */
    if (p->kind != ORR_PROJ_ORTHOGRAPHIC)
        snprintf(out, size, "%s%ssr-1", w, w[0] ? " " : "");
    else if (l[0])
        snprintf(out, size, "%s%s%s-2", w, w[0] ? " " : "", l);
    else
        snprintf(out, size, "%s", ""); /* per an unknown area: no unit can say it */
}
