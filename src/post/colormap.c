#include "post/colormap.h"

#include <math.h>
#include <string.h>

#include "post/colormap_data.h"

static const char *const colormap_names[] = {
    [ORR_CMAP_GREY] = "grey",
    [ORR_CMAP_MAGMA] = "magma",
    [ORR_CMAP_INFERNO] = "inferno",
};
#define COLORMAP_COUNT ((int)(sizeof colormap_names / sizeof colormap_names[0]))

int orr_colormap_from_name(const char *name, orr_colormap_kind *kind)
{
    if (!name)
        return 0;
    if (strcmp(name, "gray") == 0) { /* American spelling, same map */
        *kind = ORR_CMAP_GREY;
        return 1;
    }
    for (int i = 0; i < COLORMAP_COUNT; i++) {
        if (strcmp(name, colormap_names[i]) == 0) {
            *kind = (orr_colormap_kind)i;
            return 1;
        }
    }
    return 0;
}

const char *orr_colormap_name(orr_colormap_kind kind)
{
    if ((int)kind < 0 || (int)kind >= COLORMAP_COUNT)
        return "unknown";
    return colormap_names[kind];
}

const char *orr_colormap_names(void)
{
    return "grey magma inferno";
}

/* Linear interpolation between the two table entries around t. */
static void table_lookup(const float table[ORR_CMAP_ENTRIES][3], float t, float rgb[3])
{
    float x = t * (ORR_CMAP_ENTRIES - 1);
    int i = (int)x;
    if (i > ORR_CMAP_ENTRIES - 2)
        i = ORR_CMAP_ENTRIES - 2; /* t == 1 lands exactly on the last entry */
    float f = x - (float)i;
    for (int c = 0; c < 3; c++)
        rgb[c] = table[i][c] + f * (table[i + 1][c] - table[i][c]);
}

void orr_colormap_lookup(orr_colormap_kind kind, float t, float rgb[3])
{
    /* NaN fails both comparisons and becomes 0, like a negative value. */
    if (!(t > 0))
        t = 0;
    else if (t > 1)
        t = 1;
    switch (kind) {
    case ORR_CMAP_MAGMA:
        table_lookup(orr_cmap_magma, t, rgb);
        break;
    case ORR_CMAP_INFERNO:
        table_lookup(orr_cmap_inferno, t, rgb);
        break;
    case ORR_CMAP_GREY:
    default:
        rgb[0] = rgb[1] = rgb[2] = t;
        break;
    }
}
