#include "render/map_alpha.h"

#include <stdlib.h>

void orr_map_alpha_fill(const orr_projection *p, float *alpha)
{
    for (int j = 0; j < p->height; j++)
        for (int i = 0; i < p->width; i++)
            alpha[(size_t)j * (size_t)p->width + (size_t)i] = orr_projection_pixel_in_map(p, i, j) ? 1.0f : 0.0f;
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
            int on = orr_projection_pixel_in_map(p, i, j);
            for (int c = 0; c < 3; c++)
                out[4 * at + (size_t)c] = on ? rgb[3 * at + (size_t)c] : 0.0f;
            out[4 * at + 3] = on ? 1.0f : 0.0f;
        }
    *rgba = out;
    return ORR_OK;
}
