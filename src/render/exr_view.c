#include "render/exr_view.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "encode/exr.h"
#include "post/colour.h"
#include "render/map_alpha.h"

static orr_status add_channel(orr_exr_view *v, const orr_projection *p, const char *prefix, const char *name,
                              orr_error *err)
{
    char full[ORR_PLANE_NAME_MAX];
    int len = snprintf(full, sizeof full, "%s%s", prefix, name);
    if (len < 0 || (size_t)len >= sizeof full)
        return orr_fail(err, ORR_ERR_INTERNAL, "OpenEXR channel name %s%s is too long", prefix, name);
    orr_status st = orr_plane_alloc(&v->channels[v->n], p->width, p->height, full, "", err);
    if (st == ORR_OK)
        v->n++;
    return st;
}

/* Off the map a plane holds NaN (FITS's blank): a compositor wants 0 there,
 * and the alpha to say it is empty. */
static float finite_or_zero(float x) { return isfinite(x) ? x : 0.0f; }

/* R, G, B (rgb[0..2]) from X, Y, Z, unclipped and unstretched: the light
 * itself. */
static void fill_rgb(orr_plane *rgb_out, const orr_plane *xyz, size_t npix)
{
    for (size_t i = 0; i < npix; i++) {
        double in[3], rgb[3];
        for (int k = 0; k < 3; k++)
            in[k] = finite_or_zero(xyz[k].data[i]);
        orr_xyz_to_linear_srgb(in, rgb);
        for (int k = 0; k < 3; k++)
            rgb_out[k].data[i] = (float)rgb[k];
    }
}

static void copy_finite(orr_plane *to, const orr_plane *from, size_t npix)
{
    for (size_t i = 0; i < npix; i++)
        to->data[i] = finite_or_zero(from->data[i]);
}

/* OpenEXR's colour is premultiplied by its alpha: on the map's outline a
 * pixel shows its light times the share of it inside (1 elsewhere on the
 * map). The data layers (xyz.*, the populations') stay as the FITS file's. */
static void premultiply(orr_plane *colour, int n, const orr_plane *alpha, size_t npix)
{
    for (int k = 0; k < n; k++)
        for (size_t i = 0; i < npix; i++)
            colour[k].data[i] *= alpha->data[i];
}

/* A population's layer NAME.R, NAME.G, NAME.B, NAME.A from its planes
 * NAME.X, NAME.Y, NAME.Z (render/plan.c), as the beauty's R, G, B, A are
 * made from X, Y, Z: the populations' R, G, B sum to the beauty's (the
 * matrix is linear), and each layer's A is the map's coverage, the
 * beauty's A. */
static orr_status add_population_layer(orr_exr_view *v, const orr_plane *pop_xyz, const orr_projection *p,
                                       const char *prefix, orr_error *err)
{
    static const char *const rgba[] = {"R", "G", "B", "A"};
    size_t npix = (size_t)p->width * (size_t)p->height;
    const char *name = pop_xyz[0].name; /* NAME.X */
    int len = (int)strlen(name) - 2;
    orr_plane *layer = &v->channels[v->n];
    orr_status st = ORR_OK;
    for (int c = 0; c < 4 && !st; c++) {
        char full[ORR_PLANE_NAME_MAX];
        snprintf(full, sizeof full, "%.*s.%s", len, name, rgba[c]);
        st = add_channel(v, p, prefix, full, err);
    }
    if (st)
        return st;
    fill_rgb(layer, pop_xyz, npix);
    copy_finite(&layer[3], &v->channels[3], npix); /* the beauty's A */
    premultiply(layer, 3, &layer[3], npix);
    return ORR_OK;
}

static orr_status build(orr_exr_view *v, const orr_plane *planes, int nplanes, const orr_projection *p,
                        const char *prefix, orr_error *err)
{
    size_t npix = (size_t)p->width * (size_t)p->height;
    static const char *const colour_names[] = {"R", "G", "B", "A", "xyz.X", "xyz.Y", "xyz.Z"};
    static const char *const weight_names[] = {"Y", "A"};
    int colour = nplanes >= 3;
    const char *const *names = colour ? colour_names : weight_names;
    int count = colour ? 7 : 2;
    orr_status st = ORR_OK;
    for (int k = 0; k < count && !st; k++)
        st = add_channel(v, p, prefix, names[k], err);
    if (st)
        return st;
    if (colour) {
        fill_rgb(v->channels, planes, npix);
        orr_map_alpha_fill(p, v->channels[3].data);
        premultiply(v->channels, 3, &v->channels[3], npix);
        for (int k = 0; k < 3; k++)
            copy_finite(&v->channels[4 + k], &planes[k], npix);
        for (int k = 3; k + 2 < nplanes && !st; k += 3)
            st = add_population_layer(v, &planes[k], p, prefix, err);
    } else {
        copy_finite(&v->channels[0], &planes[0], npix);
        orr_map_alpha_fill(p, v->channels[1].data);
        premultiply(v->channels, 1, &v->channels[1], npix);
    }
    return st;
}

orr_status orr_exr_view_build(orr_exr_view *out, const orr_plane *planes, int nplanes, const orr_projection *p,
                              const char *prefix, orr_error *err)
{
    memset(out, 0, sizeof *out);
    if (nplanes != 1 && (nplanes < 3 || nplanes > ORR_PLANES_MAX || nplanes % 3 != 0))
        return orr_fail(err, ORR_ERR_INTERNAL, "OpenEXR view of %d planes (1, or X, Y, Z and X, Y, Z per "
                                               "population expected)", nplanes);
    orr_status st = build(out, planes, nplanes, p, prefix, err);
    if (st)
        orr_exr_view_free(out);
    return st;
}

orr_status orr_exr_view_add(orr_exr_view *v, const orr_plane *plane, const orr_projection *p, const char *name,
                            orr_error *err)
{
    if (v->n >= ORR_EXR_VIEW_MAX)
        return orr_fail(err, ORR_ERR_INTERNAL, "OpenEXR view: no room for channel %s", name);
    orr_status st = add_channel(v, p, "", name, err);
    if (!st)
        copy_finite(&v->channels[v->n - 1], plane, (size_t)p->width * (size_t)p->height);
    return st;
}

void orr_exr_view_free(orr_exr_view *v)
{
    for (int k = 0; k < v->n; k++)
        orr_plane_free(&v->channels[k]);
    v->n = 0;
}

orr_status orr_exr_view_write(const char *path, const orr_plane *channels, int n, int half,
                              const orr_image_meta *meta, orr_error *err)
{
    const orr_plane *list[2 * ORR_EXR_VIEW_MAX];
    if (n < 1 || n > 2 * ORR_EXR_VIEW_MAX)
        return orr_fail(err, ORR_ERR_INTERNAL, "%s: %d OpenEXR channels", path, n);
    for (int k = 0; k < n; k++)
        list[k] = &channels[k];
    return orr_write_exr(path, list, n, half ? ORR_EXR_HALF : ORR_EXR_FLOAT, meta, err);
}
