#include "render/path_overview.h"

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/plane.h"
#include "encode/png.h"
#include "frame/projection.h"
#include "post/colormap.h"
#include "post/stretch.h"
#include "splat/deposit.h"

/* Particles moved into the view per pass: as the renderer's blocks. */
#define BLOCK 4096

/* ---- the view ---- */

orr_vec3 orr_path_main_axis(const orr_camera_path *path, const orr_camera *cams, long n)
{
    if (path->kind == ORR_PATH_ORBIT || path->kind == ORR_PATH_INSPIRAL || path->kind == ORR_PATH_ROTATE)
        return orr_v3_normalize(path->axis);
    /* Newell's method: the sum of the cross products of successive points
     * (about their mean) is the normal of the plane they wind around,
     * weighted by the area swept, so it is robust to small wobbles. */
    orr_vec3 mean = orr_v3(0, 0, 0);
    for (long i = 0; i < n; i++)
        mean = orr_v3_add(mean, orr_v3_scale(cams[i].position, 1.0 / (double)n));
    orr_vec3 normal = orr_v3(0, 0, 0), spread = orr_v3(0, 0, 0);
    double extent2 = 0;
    for (long i = 0; i + 1 < n; i++) {
        orr_vec3 a = orr_v3_sub(cams[i].position, mean), b = orr_v3_sub(cams[i + 1].position, mean);
        normal = orr_v3_add(normal, orr_v3_cross(a, b));
        extent2 = fmax(extent2, orr_v3_dot(a, a));
    }
    if (orr_v3_norm(normal) > 1e-6 * extent2)
        return orr_v3_normalize(normal);
    /* On a line (or a point): look across it, down z unless the line runs along z. */
    if (n > 1)
        spread = orr_v3_normalize(orr_v3_sub(cams[n - 1].position, cams[0].position));
    if (fabs(spread.z) < 0.9)
        return orr_v3(0, 0, 1);
    return fabs(spread.y) < fabs(spread.x) ? orr_v3(0, 1, 0) : orr_v3(1, 0, 0);
}

/* A world axis not near the normal, for the picture's up. */
static orr_vec3 picture_up(orr_vec3 normal)
{
    static const orr_vec3 candidates[] = {{0, 1, 0}, {0, 0, 1}, {1, 0, 0}};
    for (int i = 0; i < 3; i++)
        if (fabs(orr_v3_dot(normal, candidates[i])) < 0.9)
            return candidates[i];
    return candidates[2];
}

typedef struct bounds {
    double lo[2], hi[2];
} bounds;

static void bounds_add(bounds *b, double x, double y)
{
    b->lo[0] = fmin(b->lo[0], x);
    b->hi[0] = fmax(b->hi[0], x);
    b->lo[1] = fmin(b->lo[1], y);
    b->hi[1] = fmax(b->hi[1], y);
}

/* The particles' weights, or an error naming the fields there are. */
static const float *weights_of(const orr_path_scene *ps, const orr_chunk *c)
{
    return orr_chunk_field(c, ps->source.input->weight);
}

static int selected(const orr_path_scene *ps, const orr_chunk *c, size_t i)
{
    /* input.types is a mask of types 0..5; a text table may hold others. */
    return c->type[i] < 32 && (ps->source.input->type_mask >> c->type[i] & 1u) && isfinite(c->x[i]) &&
           isfinite(c->y[i]) && isfinite(c->z[i]);
}

/* Pass 1: the particles' extent in the view's plane. */
static orr_status particle_bounds(const orr_path_scene *ps, orr_source *src, orr_mat3 to_view, bounds *b,
                                  orr_error *err)
{
    for (;;) {
        const orr_chunk *c;
        orr_status st = orr_source_next(src, &c, err);
        if (st || c->n == 0)
            return st;
        for (size_t i = 0; i < c->n; i++) {
            if (!selected(ps, c, i))
                continue;
            orr_vec3 p = orr_mat3_apply(to_view, orr_v3(c->x[i], c->y[i], c->z[i]));
            bounds_add(b, p.x, p.y);
        }
    }
}

/* ---- the splat ---- */

typedef struct block {
    float x[BLOCK], y[BLOCK], z[BLOCK], w[BLOCK], px[BLOCK], py[BLOCK], scale[BLOCK];
    uint8_t visible[BLOCK];
} block;

/* Pass 2: every selected particle deposited (cloud in cell) into plane. */
static orr_status splat_particles(const orr_path_scene *ps, orr_source *src, const orr_projection *proj,
                                  const orr_camera *view, orr_plane *plane, orr_path_overview *ov, orr_error *err)
{
    block *b = orr_malloc(sizeof *b, "overview block", err);
    if (!b)
        return ORR_ERR_NOMEM;
    const orr_mat3 m = orr_camera_world_to_camera(view);
    orr_deposit_stats stats = {0};
    orr_status st = orr_source_rewind(src, err);
    while (!st) {
        const orr_chunk *c;
        if ((st = orr_source_next(src, &c, err)) || c->n == 0)
            break;
        const float *w = weights_of(ps, c);
        if (!w) {
            st = orr_fail(err, ORR_ERR_USAGE, "%s: input.weight '%s' is not a field of %s", ps->scene_path,
                          ps->source.input->weight, src->info.path);
            break;
        }
        size_t n = 0;
        for (size_t i = 0; i <= c->n; i++) {
            if (n == BLOCK || (i == c->n && n > 0)) {
                orr_project_batch(proj, n, b->x, b->y, b->z, b->px, b->py, b->scale, b->visible);
                orr_deposit(ORR_DEPOSIT_CIC, plane, n, b->px, b->py, b->w, b->visible, proj, &stats);
                n = 0;
            }
            if (i == c->n || !selected(ps, c, i))
                continue;
            orr_vec3 p = orr_mat3_apply(m, orr_v3_sub(orr_v3(c->x[i], c->y[i], c->z[i]), view->position));
            b->x[n] = (float)p.x;
            b->y[n] = (float)p.y;
            b->z[n] = (float)p.z;
            b->w[n] = w[i];
            n++;
            ov->n_particles++;
        }
    }
    free(b);
    return st;
}

/* ---- drawing ---- */

typedef struct canvas {
    float *rgb;
    int width, height;
} canvas;

static void plot(const canvas *cv, int i, int j, const float colour[3])
{
    if (i < 0 || j < 0 || i >= cv->width || j >= cv->height)
        return;
    float *px = &cv->rgb[3 * ((size_t)j * (size_t)cv->width + (size_t)i)];
    memcpy(px, colour, 3 * sizeof(float));
}

/* Liang-Barsky: clips the segment to a margin around the picture, so a
 * path running far outside it costs nothing. Returns 0 when nothing is left. */
static int clip_segment(const canvas *cv, double *x0, double *y0, double *x1, double *y1)
{
    const double lo[2] = {-2, -2}, hi[2] = {cv->width + 2.0, cv->height + 2.0};
    const double d[2] = {*x1 - *x0, *y1 - *y0}, p0[2] = {*x0, *y0};
    double t0 = 0, t1 = 1;
    for (int k = 0; k < 2; k++) {
        const double edges[2][2] = {{-d[k], p0[k] - lo[k]}, {d[k], hi[k] - p0[k]}};
        for (int e = 0; e < 2; e++) {
            double p = edges[e][0], q = edges[e][1];
            if (p == 0) {
                if (q < 0)
                    return 0;
                continue;
            }
            double r = q / p;
            if (p < 0)
                t0 = fmax(t0, r);
            else
                t1 = fmin(t1, r);
        }
    }
    if (t0 > t1)
        return 0;
    *x1 = p0[0] + t1 * d[0];
    *y1 = p0[1] + t1 * d[1];
    *x0 = p0[0] + t0 * d[0];
    *y0 = p0[1] + t0 * d[1];
    return 1;
}

/* A line two pixels wide, visible over a busy background. */
static void draw_line(const canvas *cv, double x0, double y0, double x1, double y1, const float colour[3])
{
    if (!isfinite(x0) || !isfinite(y0) || !isfinite(x1) || !isfinite(y1) || !clip_segment(cv, &x0, &y0, &x1, &y1))
        return;
    int steps = (int)ceil(fmax(fabs(x1 - x0), fabs(y1 - y0))) + 1;
    for (int k = 0; k <= steps; k++) {
        double t = (double)k / steps;
        int i = (int)floor(x0 + t * (x1 - x0)), j = (int)floor(y0 + t * (y1 - y0));
        plot(cv, i, j, colour);
        plot(cv, i + 1, j, colour);
        plot(cv, i, j + 1, colour);
    }
}

static void draw_square(const canvas *cv, double x, double y, int half, const float colour[3])
{
    if (!isfinite(x) || !isfinite(y) || fabs(x) > 1e7 || fabs(y) > 1e7)
        return;
    for (int dj = -half; dj <= half; dj++)
        for (int di = -half; di <= half; di++)
            plot(cv, (int)floor(x) + di, (int)floor(y) + dj, colour);
}

static const float PATH_COLOUR[3] = {1.0f, 0.85f, 0.1f};
static const float TICK_COLOUR[3] = {0.2f, 0.9f, 1.0f};
static const float START_COLOUR[3] = {0.2f, 1.0f, 0.3f};
static const float END_COLOUR[3] = {1.0f, 0.25f, 0.2f};

/* A camera's place in the picture, and its view direction there (pixels). */
static void to_picture(const orr_projection *proj, const orr_camera *view, const orr_camera *cam, double *x,
                       double *y, double *dx, double *dy)
{
    const orr_mat3 m = orr_camera_world_to_camera(view);
    orr_vec3 p = orr_mat3_apply(m, orr_v3_sub(cam->position, view->position));
    orr_vec3 f = orr_mat3_apply(m, orr_quat_rotate(cam->orientation, orr_v3(0, 0, 1)));
    double scale;
    *x = *y = NAN;
    orr_project_point(proj, p, x, y, &scale);
    *dx = f.x; /* orthographic: image axes are the camera's x and y */
    *dy = f.y;
}

/* The path as a polyline, a tick with an arrow head along the view
 * direction about twenty times over, and the start and end marked. A tick
 * is shortened by how much the view points out of the picture's plane. */
static void draw_path(const canvas *cv, const orr_projection *proj, const orr_camera *view, const orr_camera *cams,
                      long n)
{
    const double tick = 0.05 * fmin(cv->width, cv->height);
    const long every = n > 20 ? (n + 19) / 20 : 1;
    double px = 0, py = 0, dx, dy;
    for (long i = 0; i < n; i++) {
        double x, y;
        to_picture(proj, view, &cams[i], &x, &y, &dx, &dy);
        if (i > 0)
            draw_line(cv, px, py, x, y, PATH_COLOUR);
        px = x;
        py = y;
    }
    for (long i = 0; i < n; i += every) {
        double x, y;
        to_picture(proj, view, &cams[i], &x, &y, &dx, &dy);
        double ex = x + tick * dx, ey = y + tick * dy, len = hypot(dx, dy);
        draw_line(cv, x, y, ex, ey, TICK_COLOUR);
        if (len > 0.2) { /* the head: two strokes back from the tip at +-30 degrees */
            double ux = dx / len, uy = dy / len, h = 0.35 * tick * len;
            for (int side = -1; side <= 1; side += 2) {
                double c = cos(ORR_PI / 6), s = side * sin(ORR_PI / 6);
                draw_line(cv, ex, ey, ex - h * (c * ux - s * uy), ey - h * (s * ux + c * uy), TICK_COLOUR);
            }
        }
    }
    /* The start last, so a closed loop shows where it begins. */
    double x, y;
    to_picture(proj, view, &cams[n - 1], &x, &y, &dx, &dy);
    draw_square(cv, x, y, 3, END_COLOUR);
    to_picture(proj, view, &cams[0], &x, &y, &dx, &dy);
    draw_square(cv, x, y, 3, START_COLOUR);
}

/* ---- the whole picture ---- */

/* Chooses the view: down the main axis, centred on and holding the path
 * (and the particles, unless fit_path). */
static orr_status choose_view(const orr_path_scene *ps, orr_source *src, const orr_camera *cams, long n,
                              orr_path_overview *ov, orr_projection *proj, orr_error *err)
{
    ov->normal = orr_path_main_axis(ps->camera_path, cams, n);
    orr_camera at_origin;
    orr_status st = orr_camera_look_along(&at_origin, orr_v3(0, 0, 0), orr_v3_scale(ov->normal, -1),
                                          picture_up(ov->normal), 0, err);
    if (st)
        return st;
    const orr_mat3 to_view = orr_camera_world_to_camera(&at_origin);
    bounds b = {{DBL_MAX, DBL_MAX}, {-DBL_MAX, -DBL_MAX}};
    for (long i = 0; i < n; i++) {
        orr_vec3 p = orr_mat3_apply(to_view, cams[i].position);
        bounds_add(&b, p.x, p.y);
    }
    if (!ov->fit_path && (st = particle_bounds(ps, src, to_view, &b, err)))
        return st;
    const double aspect = (double)ov->width / ov->height;
    double span = fmax(b.hi[0] - b.lo[0], (b.hi[1] - b.lo[1]) * aspect);
    if (!(span > 0)) /* one point: a rotate path, say */
        span = 1.0;
    ov->view_width = 1.1 * span;
    orr_vec3 centre_view = orr_v3(0.5 * (b.lo[0] + b.hi[0]), 0.5 * (b.lo[1] + b.hi[1]), 0);
    ov->view = at_origin;
    ov->view.position = orr_quat_rotate(at_origin.orientation, centre_view);
    const orr_projection_settings overview = {
        .kind = ORR_PROJ_ORTHOGRAPHIC, .width = ov->width, .height = ov->height, .ortho_width = ov->view_width};
    st = orr_projection_check(&overview, err);
    return st ? st : orr_projection_plan(proj, &overview, err);
}

/* The particles in grey (the scene's stretch), dimmed so the path stands out. */
static orr_status grade(const orr_stretch *stretch, const orr_plane *plane, float *rgb, orr_error *err)
{
    const size_t npix = (size_t)plane->width * (size_t)plane->height;
    float *t = orr_malloc(npix * sizeof(float), "overview stretch", err);
    if (!t)
        return ORR_ERR_NOMEM;
    double white;
    orr_status st = ORR_OK;
    if (orr_plane_sum(plane) > 0)
        st = orr_stretch_apply(stretch, plane, t, &white, err);
    else
        memset(t, 0, npix * sizeof(float));
    for (size_t i = 0; !st && i < npix; i++) {
        orr_colormap_lookup(ORR_CMAP_GREY, t[i], &rgb[3 * i]);
        for (int k = 0; k < 3; k++)
            rgb[3 * i + k] *= 0.75f;
    }
    free(t);
    return st;
}

orr_status orr_path_overview_write(const orr_path_scene *ps, const orr_camera *cams, long n, orr_path_overview *ov,
                                   const char *png_path, orr_error *err)
{
    if (n < 1)
        return orr_fail(err, ORR_ERR_USAGE, "path overview: no frames");
    if (ov->width < 16 || ov->height < 16 || ov->width > ORR_IMAGE_SIDE_MAX || ov->height > ORR_IMAGE_SIDE_MAX)
        return orr_fail(err, ORR_ERR_USAGE, "path overview: size %dx%d is out of range (16 to %d pixels a side)",
                        ov->width, ov->height, ORR_IMAGE_SIDE_MAX);
    ov->n_particles = 0;
    orr_source *src = NULL;
    orr_projection proj;
    orr_plane plane = {0};
    float *rgb = NULL;
    orr_status st = orr_source_request_open(&ps->source, NULL, 0, &src, err);
    if (!st)
        st = choose_view(ps, src, cams, n, ov, &proj, err);
    if (!st)
        st = orr_plane_alloc(&plane, ov->width, ov->height, ps->source.input->weight, "", err);
    if (!st)
        st = splat_particles(ps, src, &proj, &ov->view, &plane, ov, err);
    if (!st && !(rgb = orr_malloc((size_t)ov->width * (size_t)ov->height * 3 * sizeof(float), "overview", err)))
        st = ORR_ERR_NOMEM;
    if (!st)
        st = grade(ps->stretch, &plane, rgb, err);
    if (!st) {
        canvas cv = {rgb, ov->width, ov->height};
        draw_path(&cv, &proj, &ov->view, cams, n);
        char desc[ORR_PATH_MAX + 160];
        snprintf(desc, sizeof desc,
                 "camera path (%s, %ld frames) of %s over its particles, seen down (%.4g, %.4g, %.4g)",
                 orr_path_kind_name(ps->camera_path->kind), n, ps->scene_path, ov->normal.x, ov->normal.y,
                 ov->normal.z);
        orr_png_text text[] = {{"Software", "orrery " ORRERY_VERSION}, {"Description", desc}};
        st = orr_write_png_rgb(png_path, ov->width, ov->height, rgb, 8, text, 2, err);
    }
    free(rgb);
    orr_plane_free(&plane);
    orr_source_close(src);
    return st;
}
