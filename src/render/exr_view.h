/* A view's linear planes as a compositor reads an OpenEXR file: scene-linear
 * RGB (Rec. 709 primaries, D65) in R, G, B from the X, Y, Z planes, with
 * the CIE planes kept as the layer xyz.X, xyz.Y, xyz.Z (a bare "Z" is depth
 * to Nuke, Blender and After Effects); a single weight plane as luminance Y;
 * and an alpha A, each pixel's coverage of the map (1 inside a dome's
 * circle, a Hammer-Aitoff ellipse, everywhere on the others), 0 off it,
 * where every colour is 0, not NaN; colour premultiplied by it. With
 * output.exr_population_layers the planes after X, Y, Z (each population's
 * X, Y, Z, named NAME.X, NAME.Y, NAME.Z) become the layers NAME.R, NAME.G,
 * NAME.B, NAME.A, made as R, G, B, A are, so they sum to them.
 * docs/formats-out.md. */
#ifndef ORR_RENDER_EXR_VIEW_H
#define ORR_RENDER_EXR_VIEW_H

#include "core/error.h"
#include "encode/image_out.h"
#include "frame/projection.h"
#include "core/plane.h"

/* R, G, B, A, xyz.X, xyz.Y, xyz.Z, NAME.R, .G, .B, .A per population, and
 * the dust's extinction.V (A_V) */
#define ORR_EXR_VIEW_MAX (8 + 4 * ORR_POPULATION_LAYERS_MAX)

typedef struct orr_exr_view {
    int n;
    orr_plane channels[ORR_EXR_VIEW_MAX];
} orr_exr_view;

/* Builds the channels of planes (1 weight plane, or X, Y, Z and each
 * population's X, Y, Z, named NAME.X, ...), each name
 * prefixed with prefix ("" or a stereo eye's "left."). p is the view's
 * projection, for the alpha. On failure nothing stays allocated. */
orr_status orr_exr_view_build(orr_exr_view *out, const orr_plane *planes, int nplanes, const orr_projection *p,
                              const char *prefix, orr_error *err);
/* Adds one more channel, named name, holding plane (NaN as 0): the dust's
 * extinction plane beside the light (dust.extinction_plane). */
orr_status orr_exr_view_add(orr_exr_view *v, const orr_plane *plane, const orr_projection *p, const char *name,
                            orr_error *err);
void orr_exr_view_free(orr_exr_view *v);

/* Writes n channels (one view's, or both eyes' of a stereo pair) to path
 * as OpenEXR: half samples when half (output.exr_half), else float. */
orr_status orr_exr_view_write(const char *path, const orr_plane *channels, int n, int half,
                              const orr_image_meta *meta, orr_error *err);

#endif
