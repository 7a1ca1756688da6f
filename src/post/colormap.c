#include "post/colormap.h"

#include <math.h>
#include <string.h>

#include "post/colormap_data.h"

/* "gray", the American spelling of the same map, is read but not listed. */
const orr_named orr_colormap_kind_names[] = {
    {"grey", ORR_CMAP_GREY}, {"magma", ORR_CMAP_MAGMA}, {"inferno", ORR_CMAP_INFERNO}, {"gray", ORR_CMAP_GREY}, {NULL, 0}};

ORR_NAMED_PARSER(orr_colormap_from_name, orr_colormap_kind, orr_colormap_kind_names)

const char *orr_colormap_name(orr_colormap_kind kind) { return orr_named_name(orr_colormap_kind_names, (int)kind); }

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
