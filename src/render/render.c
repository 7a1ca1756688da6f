#include "render/render.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "encode/atomic.h"
#include "encode/fits.h"
#include "encode/png.h"
#include "post/colormap.h"
#include "post/stretch.h"
#include "source/model.h"

/* Particles are processed in blocks of this many: the block's scratch arrays
 * (about 100 KiB) stay in L2 cache between the gather, project and deposit
 * passes. */
#define BLOCK 4096

typedef struct block_buffers {
    float x[BLOCK], y[BLOCK], z[BLOCK], w[BLOCK];
    float px[BLOCK], py[BLOCK], scale[BLOCK];
    uint8_t visible[BLOCK];
} block_buffers;

orr_status orr_scene_camera(const orr_scene *s, orr_camera *cam, orr_error *err)
{
    if (s->has_quaternion) {
        cam->position = s->camera_position;
        cam->orientation = orr_quat_normalize(s->camera_quaternion);
        return ORR_OK;
    }
    if (s->has_look_at)
        return orr_camera_look_at(cam, s->camera_position, s->camera_look_at, s->camera_up, s->camera_roll, err);
    if (s->has_direction && !s->has_up)
        return orr_camera_look_along_roll(cam, s->camera_position, s->camera_direction, s->camera_roll, err);
    orr_vec3 dir = s->has_direction ? s->camera_direction : orr_v3(0, 0, -1);
    return orr_camera_look_along(cam, s->camera_position, dir, s->camera_up, s->camera_roll, err);
}

orr_status orr_scene_open_source(const orr_scene *s, orr_source **out, orr_error *err)
{
    if (s->model_name[0]) {
        orr_model_params mp = {s->model_particles, s->model_seed, s->model_separation};
        return orr_model_source_open(&mp, (size_t)s->chunk_size, out, err);
    }
    /* Ask only for what the render uses, so readers can skip the rest. */
    int extra = strcmp(s->weight, "mass") != 0 && strcmp(s->weight, "h") != 0;
    const char *const fields[1] = {s->weight};
    orr_source_options opt = {s->input_format, (size_t)s->chunk_size, s->type_mask, fields, extra ? 1 : 0};
    return orr_source_open_file(s->input_file, &opt, out, err);
}

/* The weight array of a chunk, or an error listing the fields there are. */
static orr_status weight_field(const orr_scene *s, const orr_source *src, const orr_chunk *c,
                               const float **w, orr_error *err)
{
    *w = orr_chunk_field(c, s->weight);
    if (*w)
        return ORR_OK;
    char have[512] = "mass";
    if (c->h)
        strncat(have, ", h", sizeof have - strlen(have) - 1);
    for (int i = 0; i < c->nextra; i++) {
        strncat(have, ", ", sizeof have - strlen(have) - 1);
        strncat(have, c->extra[i].name, sizeof have - strlen(have) - 1);
    }
    return orr_fail(err, ORR_ERR_USAGE, "%s: input.weight '%s' is not a field of %s (fields: %s)", s->path,
                    s->weight, src->info.path, have);
}

static orr_status nonfinite_error(const orr_source *src, const orr_chunk *c, size_t i, const char *what,
                                  orr_error *err)
{
    return orr_fail(err, ORR_ERR_DATA,
                    "%s: particle %llu (id %llu) has a non-finite %s (%g, %g, %g); "
                    "set input.nonfinite: skip to leave such particles out",
                    src->info.path, (unsigned long long)(c->first_index + i), (unsigned long long)c->id[i], what,
                    (double)c->x[i], (double)c->y[i], (double)c->z[i]);
}

/* Gathers the selected particles of c[start, end) into the block, already
 * moved into the camera frame; returns how many, or -1 on a bad particle
 * when the scene says to fail. */
static long gather_block(const orr_scene *s, const orr_source *src, const orr_chunk *c, const float *wsrc,
                         size_t start, size_t end, const orr_mat3 *R, orr_vec3 origin, block_buffers *b,
                         orr_render_report *rep, orr_error *err)
{
    const float r00 = (float)R->m[0][0], r01 = (float)R->m[0][1], r02 = (float)R->m[0][2];
    const float r10 = (float)R->m[1][0], r11 = (float)R->m[1][1], r12 = (float)R->m[1][2];
    const float r20 = (float)R->m[2][0], r21 = (float)R->m[2][1], r22 = (float)R->m[2][2];
    /* Subtracting the origin in double keeps precision for cameras far from
     * the coordinate origin (e.g. inside a big box). */
    long n = 0;
    for (size_t i = start; i < end; i++) {
        if (!(s->type_mask & (1u << c->type[i])))
            continue;
        rep->n_selected++;
        if (!isfinite(c->x[i]) || !isfinite(c->y[i]) || !isfinite(c->z[i]) || !isfinite(wsrc[i])) {
            if (!s->skip_nonfinite) {
                nonfinite_error(src, c, i, isfinite(wsrc[i]) ? "position" : "weight", err);
                return -1;
            }
            rep->n_nonfinite++;
            continue;
        }
        float dx = (float)((double)c->x[i] - origin.x);
        float dy = (float)((double)c->y[i] - origin.y);
        float dz = (float)((double)c->z[i] - origin.z);
        b->x[n] = r00 * dx + r01 * dy + r02 * dz;
        b->y[n] = r10 * dx + r11 * dy + r12 * dz;
        b->z[n] = r20 * dx + r21 * dy + r22 * dz;
        b->w[n] = wsrc[i];
        n++;
    }
    return n;
}

orr_status orr_splat_source(const orr_scene *s, const orr_camera *cam, const orr_projection *proj,
                            orr_source *src, orr_plane *plane, orr_render_report *rep, orr_progress_fn progress,
                            void *progress_user, orr_error *err)
{
    block_buffers *b = orr_malloc(sizeof *b, "splat block buffers", err);
    if (!b)
        return ORR_ERR_NOMEM;
    orr_mat3 R = orr_camera_world_to_camera(cam);
    orr_status st = ORR_OK;
    for (;;) {
        const orr_chunk *c;
        if ((st = orr_source_next(src, &c, err)))
            break;
        if (c->n == 0)
            break;
        const float *w;
        if ((st = weight_field(s, src, c, &w, err)))
            break;
        for (size_t start = 0; start < c->n; start += BLOCK) {
            size_t end = start + BLOCK < c->n ? start + BLOCK : c->n;
            long n = gather_block(s, src, c, w, start, end, &R, cam->position, b, rep, err);
            if (n < 0) {
                st = err ? err->code : ORR_ERR_DATA;
                goto done;
            }
            orr_project_batch(proj, (size_t)n, b->x, b->y, b->z, b->px, b->py, b->scale, b->visible);
            orr_deposit(s->deposit, plane, (size_t)n, b->px, b->py, b->w, b->visible, &rep->deposit);
        }
        rep->n_read += c->n;
        if (progress)
            progress(progress_user, rep->n_read, src->info.count);
    }
done:
    free(b);
    return st;
}

static void add_frame_cards(const orr_scene *s, const orr_camera *cam, const orr_projection *p,
                            const orr_render_report *rep, orr_fits_header *h)
{
    orr_fits_add_string(h, "CREATOR", "orrery " ORRERY_VERSION, "software that made this file");
    orr_fits_add_string(h, "ORRVERS", ORRERY_VERSION, "orrery version");
    orr_fits_add_string(h, "PROJTYPE", orr_projection_name(p->kind), "projection");
    if (p->kind == ORR_PROJ_ORTHOGRAPHIC) {
        orr_fits_add_double(h, "ORTHOWID", p->ortho_width, "image width in simulation length units");
    } else {
        orr_fits_add_double(h, "FOV", p->fov_deg, "[deg] field of view along the wider axis");
        orr_fits_add_double(h, "NEAR", p->near, "near plane distance");
    }
    orr_fits_add_double(h, "CAMPOSX", cam->position.x, "camera position x");
    orr_fits_add_double(h, "CAMPOSY", cam->position.y, "camera position y");
    orr_fits_add_double(h, "CAMPOSZ", cam->position.z, "camera position z");
    orr_fits_add_double(h, "CAMQW", cam->orientation.w, "camera-to-world quaternion w");
    orr_fits_add_double(h, "CAMQX", cam->orientation.x, "camera-to-world quaternion x");
    orr_fits_add_double(h, "CAMQY", cam->orientation.y, "camera-to-world quaternion y");
    orr_fits_add_double(h, "CAMQZ", cam->orientation.z, "camera-to-world quaternion z");
    orr_fits_add_long(h, "IMGWIDTH", p->width, "[pixel] image width");
    orr_fits_add_long(h, "IMGHEIGH", p->height, "[pixel] image height");
    orr_fits_add_string(h, "DEPOSIT", orr_deposit_name(s->deposit), "deposit method");
    orr_fits_add_string(h, "WEIGHT", s->weight, "particle field deposited");
    orr_fits_add_long(h, "NPART", (long long)rep->n_read, "particles read");
    orr_fits_add_long(h, "NSELECT", (long long)rep->n_selected, "particles of the selected types");
    orr_fits_add_long(h, "NSKIPPED", (long long)rep->n_nonfinite, "particles skipped as non-finite");
    orr_fits_add_long(h, "NCULLED", (long long)rep->deposit.n_culled, "particles not drawn (behind camera)");
    orr_fits_add_double(h, "WIMAGE", rep->deposit.deposited, "weight deposited in the image");
    orr_fits_add_double(h, "WOUTSIDE", rep->deposit.outside, "weight that fell off the image");
    orr_fits_add_double(h, "SIMTIME", rep->sim_time, "simulation time of the snapshot");
    const char *slash = strrchr(rep->source, '/');
    orr_fits_add_string(h, "SOURCE", slash ? slash + 1 : rep->source, "particle source");
}

static orr_status write_png(const orr_scene *s, const orr_plane *plane, const char *path,
                            orr_render_report *rep, orr_error *err)
{
    size_t npix = (size_t)plane->width * (size_t)plane->height;
    float *t = orr_malloc(npix * sizeof(float), "stretched image", err);
    float *rgb = orr_malloc(npix * 3 * sizeof(float), "PNG pixels", err);
    orr_status st = (t && rgb) ? ORR_OK : ORR_ERR_NOMEM;
    if (!st)
        st = orr_stretch_apply(&s->stretch, plane, t, &rep->white, err);
    if (!st) {
        for (size_t i = 0; i < npix; i++)
            orr_colormap_lookup(s->colormap, t[i], &rgb[3 * i]);
        char desc[ORR_PATH_MAX + 256];
        snprintf(desc, sizeof desc, "%s of %s, %s stretch, white %g, colour map %s", s->weight, rep->source,
                 orr_stretch_name(s->stretch.kind), rep->white, orr_colormap_name(s->colormap));
        orr_png_text text[] = {{"Software", "orrery " ORRERY_VERSION}, {"Description", desc}};
        st = orr_write_png_rgb(path, plane->width, plane->height, rgb, s->png_bits, text, 2, err);
    }
    free(t);
    free(rgb);
    return st;
}

static orr_status output_path(const orr_scene *s, const char *ext, char *path, orr_error *err)
{
    int n = snprintf(path, ORR_PATH_MAX, "%s/%s.%s", s->out_dir, s->out_name, ext);
    if (n < 0 || n >= ORR_PATH_MAX)
        return orr_fail(err, ORR_ERR_USAGE, "output path %s/%s.%s is too long", s->out_dir, s->out_name, ext);
    return ORR_OK;
}

static orr_status write_outputs(const orr_scene *s, const orr_camera *cam, const orr_projection *proj,
                                const orr_plane *plane, orr_render_report *rep, orr_error *err)
{
    orr_status st = ORR_OK;
    if (s->write_fits) {
        char *path = rep->outputs[rep->noutputs];
        orr_fits_header h = {0};
        add_frame_cards(s, cam, proj, rep, &h);
        if ((st = output_path(s, "fits", path, err)) || (st = orr_write_fits(path, plane, 1, &h, err)))
            return st;
        rep->noutputs++;
    }
    if (s->write_png) {
        char *path = rep->outputs[rep->noutputs];
        if ((st = output_path(s, "png", path, err)) || (st = write_png(s, plane, path, rep, err)))
            return st;
        rep->noutputs++;
    }
    return ORR_OK;
}

orr_status orr_render_scene(const orr_scene *s, orr_render_report *rep, orr_progress_fn progress,
                            void *progress_user, orr_error *err)
{
    memset(rep, 0, sizeof *rep);
    orr_camera cam;
    orr_projection proj = s->projection;
    orr_status st;
    if ((st = orr_scene_camera(s, &cam, err)) || (st = orr_projection_setup(&proj, err)))
        return orr_fail_prefix(err, "%s: ", s->path);
    /* Fail on an unwritable output folder before any slow work. */
    if ((st = orr_check_output_dir(s->out_dir, err)))
        return st;
    orr_source *src = NULL;
    if ((st = orr_scene_open_source(s, &src, err)))
        return st;
    snprintf(rep->source, sizeof rep->source, "%s", src->info.path);
    rep->sim_time = src->info.time;
    orr_plane plane;
    st = orr_plane_alloc(&plane, proj.width, proj.height, s->weight, s->bunit, err);
    if (!st) {
        st = orr_splat_source(s, &cam, &proj, src, &plane, rep, progress, progress_user, err);
        if (!st)
            st = write_outputs(s, &cam, &proj, &plane, rep, err);
        orr_plane_free(&plane);
    }
    orr_source_close(src);
    return st;
}
