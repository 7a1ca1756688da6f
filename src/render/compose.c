/* orrery compose's second half: a view's raw planes (or its layers) read
 * back, the PSF, the colour synthesis or stretch, the pictures. */
#include "render/view_state.h"

#include <errno.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>

#include "encode/fits_read.h"
#include "post/grade.h"

orr_status orr_compose_check_raw_dir(const char *output_dir, int nlayers, orr_error *err)
{
    const char *dir = output_dir[0] ? output_dir : ".";
    struct stat st;
    if (nlayers > 0 || stat(dir, &st) == 0 || errno != ENOENT)
        return ORR_OK;
    return orr_fail(err, ORR_ERR_IO,
                    "%s: no such folder: compose reads the planes `orrery render` wrote from the output "
                    "folder; give the render's -o or output.dir",
                    dir);
}

/* The reason a raw-planes file cannot be read, when it is simply not there. */
static orr_status missing_raw(const view_state *v, const char *path, orr_error *err)
{
    struct stat st;
    if (stat(path, &st) == 0 || errno != ENOENT)
        return ORR_OK;
    return orr_fail(err, ORR_ERR_IO,
                    "%s: no such file: compose reads %s; render the scene first, with the same output.dir and "
                    "output.name",
                    path, v->files.regrade_final ? "the FITS planes that `orrery render` wrote"
                                                  : "the raw planes that `orrery render` writes with output.raw: true");
}

/* One view's raw planes into its planes: the file must hold what the scene
 * renders (one weight plane, or X, Y, Z) at the scene's image size. */
static orr_status load_raw(view_state *v, orr_error *err)
{
    orr_render_report *rep = v->rep;
    char path[ORR_PATH_MAX];
    orr_status st = orr_view_output_path(&v->files.output, v->files.regrade_final ? "fits" : "raw.fits", path, err);
    orr_plane raw[3];
    int n = 0;
    if (!st)
        st = missing_raw(v, path, err);
    if (!st)
        st = orr_read_fits_planes(path, raw, 3, &n, err);
    if (!st && (n != fits_nplanes(v) || raw[0].width != v->pass.proj.width || raw[0].height != v->pass.proj.height))
        st = orr_fail(err, ORR_ERR_DATA,
                      "%s: holds %d plane(s) of %d x %d, but %s renders %d of %d x %d (was it rendered from "
                      "another scene?)",
                      path, n, raw[0].width, raw[0].height, v->files.path, fits_nplanes(v), v->pass.proj.width,
                      v->pass.proj.height);
    for (int k = 0; !st && k < n; k++)
        memcpy(v->pass.planes[k].data, raw[k].data,
               (size_t)v->pass.proj.width * (size_t)v->pass.proj.height * sizeof(float));
    for (int k = 0; k < n; k++)
        orr_plane_free(&raw[k]);
    if (!st)
        snprintf(rep->source, sizeof rep->source, "%s", path);
    return st;
}

/* Adds one layer to the view's X, Y, Z planes: a luminance plane times its
 * colour, or X, Y, Z planes as they are, times the gain. */
static orr_status add_layer(view_state *v, const struct orr_compose_layer *l, orr_error *err)
{
    orr_plane raw[3];
    int n = 0;
    orr_status st = orr_read_fits_planes(l->file, raw, 3, &n, err);
    if (!st && (raw[0].width != v->pass.proj.width || raw[0].height != v->pass.proj.height))
        st = orr_fail(err, ORR_ERR_DATA, "%s: compose.layers: the planes are %d x %d, the scene's image %d x %d",
                      l->file, raw[0].width, raw[0].height, v->pass.proj.width, v->pass.proj.height);
    if (!st && n != 1 && n != 3)
        st = orr_fail(err, ORR_ERR_DATA, "%s: compose.layers: %d planes; a layer is one luminance plane or X, Y, Z",
                      l->file, n);
    if (!st && n == 1 && !l->has_colour)
        st = orr_fail(err, ORR_ERR_USAGE, "%s: compose.layers: a single-plane layer needs a colour", l->file);
    double xyz[3] = {1, 1, 1};
    if (!st && n == 1 && (st = orr_colour_xyz(&l->colour, xyz, err)) == ORR_OK)
        orr_xyz_normalise(xyz);
    size_t npix = (size_t)v->pass.proj.width * (size_t)v->pass.proj.height;
    for (int k = 0; !st && k < 3; k++) {
        const float *src = raw[n == 1 ? 0 : k].data;
        float f = (float)(l->gain * (n == 1 ? xyz[k] : 1.0));
        for (size_t i = 0; i < npix; i++)
            v->pass.planes[k].data[i] += f * src[i];
    }
    for (int k = 0; k < n; k++)
        orr_plane_free(&raw[k]);
    return st;
}

static orr_status load_layers(view_state *v, orr_error *err)
{
    const orr_compose_settings *c = &v->files.compose;
    orr_status st = ORR_OK;
    for (int k = 0; k < c->nlayers && !st; k++)
        st = add_layer(v, &c->layers[k], err);
    if (!st)
        snprintf(v->rep->source, sizeof v->rep->source, "%d layers (%.200s, ...)", c->nlayers, c->layers[0].file);
    return st;
}

orr_status orr_view_compose(view_state *v, orr_error *err)
{
    orr_status st = v->files.compose.nlayers ? load_layers(v, err) : load_raw(v, err);
    for (int j = 0; j < v->pass.nplanes && !st && !v->files.regrade_final; j++) /* NAME.fits has its PSF */
        st = orr_view_psf_apply(&v->pass.psf, &v->pass.planes[j], err);
    if (!st) {
        orr_mask_outside_map(&v->pass.proj, v->pass.planes, v->pass.nplanes);
        st = orr_view_write_pictures(v, err);
    }
    return st;
}
