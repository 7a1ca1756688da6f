#include "splat/plane.h"

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

orr_status orr_plane_alloc(orr_plane *p, int width, int height, const char *name, const char *unit,
                           orr_error *err)
{
    memset(p, 0, sizeof *p);
    if (width <= 0 || height <= 0 || width > 65536 || height > 65536)
        return orr_fail(err, ORR_ERR_USAGE, "image size %d x %d is out of range (1 to 65536 pixels a side)",
                        width, height);
    /* Deposits address pixels with 32-bit indices (splat/deposit.h). */
    if ((size_t)width * (size_t)height > (size_t)INT32_MAX)
        return orr_fail(err, ORR_ERR_USAGE,
                        "image size %d x %d has more than 2^31 - 1 pixels (8 GiB a plane), the most orrery draws",
                        width, height);
    p->data = orr_calloc((size_t)width * (size_t)height, sizeof(float), "image plane", err);
    if (!p->data)
        return ORR_ERR_NOMEM;
    p->width = width;
    p->height = height;
    snprintf(p->name, sizeof p->name, "%s", name ? name : "");
    snprintf(p->unit, sizeof p->unit, "%s", unit ? unit : "");
    return ORR_OK;
}

void orr_plane_free(orr_plane *p)
{
    free(p->data);
    p->data = NULL;
}

double orr_plane_sum(const orr_plane *p)
{
    double s = 0;
    size_t n = (size_t)p->width * (size_t)p->height;
    for (size_t i = 0; i < n; i++)
        s += p->data[i];
    return s;
}
