/* Colour maps from a display value t in [0, 1] to sRGB-encoded RGB in [0, 1]. */
#ifndef ORR_POST_COLORMAP_H
#define ORR_POST_COLORMAP_H

typedef enum {
    ORR_CMAP_GREY,
    ORR_CMAP_MAGMA,
    ORR_CMAP_INFERNO,
} orr_colormap_kind;

/* Parses "grey" (or "gray"), "magma", "inferno"; returns 0 on an unknown name. */
int orr_colormap_from_name(const char *name, orr_colormap_kind *kind);
const char *orr_colormap_name(orr_colormap_kind kind);
/* Space-separated list of the known names, for help texts and errors. */
const char *orr_colormap_names(void);

void orr_colormap_lookup(orr_colormap_kind kind, float t, float rgb[3]);

#endif
