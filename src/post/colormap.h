/* Colour maps from a display value t in [0, 1] to sRGB-encoded RGB in [0, 1]. */
#ifndef ORR_POST_COLORMAP_H
#define ORR_POST_COLORMAP_H

#include "core/names.h"

typedef enum {
    ORR_CMAP_GREY,
    ORR_CMAP_MAGMA,
    ORR_CMAP_INFERNO,
} orr_colormap_kind;

/* "grey", "magma", "inferno" (and "gray", read as grey but not listed). */
extern const orr_named orr_colormap_kind_names[];

/* Parses "grey" (or "gray"), "magma", "inferno"; returns 0 on an unknown name. */
int orr_colormap_from_name(const char *name, orr_colormap_kind *kind);
const char *orr_colormap_name(orr_colormap_kind kind);

void orr_colormap_lookup(orr_colormap_kind kind, float t, float rgb[3]);

#endif
