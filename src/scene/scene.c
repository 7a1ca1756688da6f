#include "scene/scene.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "scene/scene_file.h"
#include "scene/scene_views.h"
#include "scene/ytree.h"

void orr_scene_defaults(orr_scene *s)
{
    memset(s, 0, sizeof *s);
    snprintf(s->path, sizeof s->path, "<built-in>");
    snprintf(s->dir, sizeof s->dir, ".");

    snprintf(s->input_format, sizeof s->input_format, "auto");
    s->model_particles = 200000;
    s->model_seed = 1;
    s->model_separation = 780;
    s->model_galaxies = 0; /* ORR_MODEL_PAIR */
    s->model_disc_q = 1.5;
    s->model_w0 = 7;
    s->model_core_radius = 1;
    s->model_mass = 5e5;
    snprintf(s->weight, sizeof s->weight, "mass");
    s->type_mask = 0x3f;
    orr_dust_settings_defaults(&s->dust);
    s->chunk_size = 1048576;
    orr_path_defaults(&s->camera_path, ORR_PATH_KEYFRAMES);
    s->skip_nonfinite = 0;
    s->periodic_box = 0;
    s->periodic_replicas = 1;
    s->periodic_around_camera = 1;
    s->anim_frames = 1;
    s->anim_fps = 30;
    s->seq_first = 0;
    s->seq_step = 1;
    s->seq_interpolation = ORR_INTERP_AUTO;
    s->seq_max_memory = 16;

    s->camera_position = orr_v3(0, 0, 0);
    s->camera_up = orr_v3(0, 1, 0);
    s->camera_roll = 0;
    s->camera_quaternion = (orr_quat){1, 0, 0, 0};

    s->projection.kind = ORR_PROJ_ORTHOGRAPHIC;
    s->projection.width = 1024;
    s->projection.height = 1024;
    s->projection.ortho_width = 100;
    s->projection.fov_deg = 60;
    s->projection.near = 1e-3;
    s->projection.dome_fov_deg = 180;
    s->projection.healpix_nside = 64;
    s->projection.lon_flip = 0;
    s->deposit = ORR_DEPOSIT_CIC;
    s->kernel = ORR_KERNEL_CUBIC;
    s->lengths = ORR_LENGTHS_AUTO;
    s->neighbours = 32;
    s->h_scale = 1.0;
    s->colour = 0;
    s->colour_seed = 1;
    s->only = -1;
    orr_population_set_init(&s->populations, 1);
    orr_colour_synth_defaults(&s->synth);
    s->psf = ORR_PSF_NONE;
    s->glow_max_arcmin = 60;
    s->psf_fwhm = 3.6; /* pixels: stars twinkle by at most 1.2x (docs/psf.md#stars-that-do-not-twinkle) */
    s->psf_fwhm_arcmin = 0; /* auto: ORR_SKY_CORE_PIXELS at the map's centre */
    s->psf_file_subsample = 1;
    s->psf_arcsec_per_pixel = 0.04;
    s->psf_angle = 45.0;
    s->psf_vane_width = 0.022; /* Hubble's (Tiny Tim's pupil tables) */
    s->psf_spike_gain = 1.0;
    s->psf_size = 129;
    s->psf_spike_stars = 200;
    s->psf_spike_min_flux = 0.001;

    s->dome_tilt = 0;
    s->zenith_lb[0] = 0;
    s->zenith_lb[1] = 90;
    s->front_lb[0] = 0;
    s->front_lb[1] = 0;

    s->observer_normal = orr_v3(0, 0, 1);
    s->normal_types = 0;
    s->normal_radius = 30;
    s->normal_sign = -1;
    s->dim = 1;
    s->dim_near = 0.01;
    s->camera_dim_near = 0.01;

    s->stereo = ORR_STEREO_NONE;
    s->eye_separation = 0;
    s->convergence = 0; /* auto */
    s->anaglyph = ORR_ANAGLYPH_DUBOIS;
    s->zenith_fade = 0;
    s->stereo_eye = 0;

    snprintf(s->out_dir, sizeof s->out_dir, ".");
    s->write_fits = 1;
    s->write_png = 1;
    s->png_bits = 8;
    s->stretch = (orr_stretch){.kind = ORR_STRETCH_LOG, .white = 0, .white_percentile = 99.9, .n = 1000};
    s->colormap = ORR_CMAP_MAGMA;
    s->frame_digits = 4;
    snprintf(s->frame_separator, sizeof s->frame_separator, "_");
}

/* ---- overrides ---- */

/* Checks the key of "key=value" and returns it trimmed in key (of size size). */
static orr_status override_key(const char *arg, const char *origin, char *key, size_t size, orr_error *err)
{
    const char *eq = strchr(arg, '=');
    if (!eq)
        return orr_fail(err, ORR_ERR_USAGE, "%s: expected key=value, e.g. camera.fov=60", origin);
    const char *b = arg, *e = eq;
    while (b < e && (*b == ' ' || *b == '\t'))
        b++;
    while (e > b && (e[-1] == ' ' || e[-1] == '\t'))
        e--;
    if (b == e)
        return orr_fail(err, ORR_ERR_USAGE, "%s: the key before '=' is empty", origin);
    if ((size_t)(e - b) >= size)
        return orr_fail(err, ORR_ERR_USAGE, "%s: the key is too long", origin);
    memcpy(key, b, (size_t)(e - b));
    key[e - b] = '\0';
    if (key[0] == '.' || key[strlen(key) - 1] == '.' || strstr(key, ".."))
        return orr_fail(err, ORR_ERR_USAGE, "%s: key '%s' has an empty part between dots", origin, key);
    return ORR_OK;
}

/* Applies one "key=value": the value is YAML flow text ("60", "[0,0,10]",
 * "{fov: 30}"), put in place of whatever the tree held at key. */
static orr_status apply_override(yt_node *root, const char *arg, const char *origin, orr_error *err)
{
    char key[256];
    orr_status st = override_key(arg, origin, key, sizeof key, err);
    if (st == ORR_OK)
        st = scene_views_check_override(root, key, origin, err);
    if (st != ORR_OK)
        return st;
    const char *text = strchr(arg, '=') + 1;
    yt_node *value = NULL;
    st = yt_parse(text, strlen(text), origin, 0, &value, err);
    if (st != ORR_OK)
        return st;
    if (!value && !(value = yt_new_scalar("", 0, origin, 0, err))) /* "key=": no value */
        return ORR_ERR_NOMEM;
    return yt_set_path(root, key, value, origin, err);
}

/* Each override's origin for messages, "--set key=value"; NULL when out of memory. */
static char **override_origins(const char *const *overrides, int n, orr_error *err)
{
    char **origins = orr_calloc((size_t)n, sizeof *origins, "override names", err);
    if (!origins)
        return NULL;
    for (int i = 0; i < n; i++) {
        size_t size = strlen(overrides[i]) + sizeof "--set ";
        origins[i] = orr_malloc(size, "an override name", err);
        if (!origins[i]) {
            for (int j = 0; j < i; j++)
                free(origins[j]);
            free(origins);
            return NULL;
        }
        snprintf(origins[i], size, "--set %s", overrides[i]);
    }
    return origins;
}

static void free_origins(char **origins, int n)
{
    if (!origins)
        return;
    for (int i = 0; i < n; i++)
        free(origins[i]);
    free(origins);
}

/* ---- loading ---- */

/* Parses the scene text into *root (freed by the caller, also on error) and
 * applies the overrides to it. */
static orr_status build_tree(yt_node **root, const char *text, const char *path, char **origins,
                             const char *const *overrides, int noverrides, orr_error *err)
{
    orr_status st = yt_parse(text, strlen(text), path, 1, root, err);
    if (st != ORR_OK)
        return st;
    if (!*root || yt_is_null(*root))
        return orr_fail(err, ORR_ERR_USAGE, "%s: the scene is empty (expected a mapping of keys such as input:)",
                        path);
    if ((*root)->kind != YT_MAPPING) {
        char got[96];
        return orr_fail(err, ORR_ERR_USAGE, "%s:%d: the top level of a scene must be a mapping of keys, not %s",
                        path, (*root)->line, yt_describe(*root, got, sizeof got));
    }
    for (int i = 0; i < noverrides; i++)
        if ((st = apply_override(*root, overrides[i], origins[i], err)) != ORR_OK)
            return st;
    return ORR_OK;
}

/* The common part of every loader: text to tree, overrides, views. */
static orr_status load_text(orr_scene_views *out, const char *text, const scene_source *src,
                            const char *const *overrides, int noverrides, orr_error *err)
{
    out->n = 0;
    if (noverrides < 0 || (noverrides > 0 && !overrides))
        return orr_fail(err, ORR_ERR_INTERNAL, "%s: bad override list (%d)", src->path, noverrides);
    char **origins = override_origins(overrides, noverrides, err);
    if (!origins)
        return ORR_ERR_NOMEM;
    yt_node *root = NULL;
    orr_status st = build_tree(&root, text, src->path, origins, overrides, noverrides, err);
    if (st == ORR_OK)
        st = scene_views_from_tree(out, root, src, err);
    yt_free(root); /* before the origins: its nodes point at them */
    free_origins(origins, noverrides);
    return st;
}

/* The default output name: the stem of name_from, or "orrery" without one. */
static void default_stem(const char *name_from, char *stem, size_t size)
{
    scene_path_stem(name_from ? name_from : "", stem, size);
    if (stem[0] == '\0')
        snprintf(stem, size, "orrery");
}

orr_status orr_scene_load_views(orr_scene_views *out, const char *path, const char *const *overrides,
                                int noverrides, orr_error *err)
{
    out->n = 0;
    if (strlen(path) >= ORR_PATH_MAX)
        return orr_fail(err, ORR_ERR_USAGE, "scene file name is too long (%zu characters)", strlen(path));
    char dir[ORR_PATH_MAX], stem[ORR_NAME_MAX];
    scene_path_dir(path, dir, sizeof dir);
    default_stem(path, stem, sizeof stem);
    char *text = NULL;
    orr_status st = scene_read_text(path, "scene file", &text, err);
    if (st != ORR_OK)
        return st;
    const scene_source src = {path, dir, stem};
    st = load_text(out, text, &src, overrides, noverrides, err);
    free(text);
    return st;
}

orr_status orr_scene_load_views_string(orr_scene_views *out, const char *yaml, const char *origin,
                                       const char *base_dir, const char *const *overrides, int noverrides,
                                       orr_error *err)
{
    out->n = 0;
    const char *path = origin ? origin : "<built-in>";
    if (strlen(path) >= ORR_PATH_MAX)
        return orr_fail(err, ORR_ERR_USAGE, "scene name is too long (%zu characters)", strlen(path));
    if (base_dir && strlen(base_dir) >= ORR_PATH_MAX)
        return orr_fail(err, ORR_ERR_USAGE, "%s: base folder name is too long", path);
    char stem[ORR_NAME_MAX];
    default_stem(origin, stem, sizeof stem);
    const scene_source src = {path, base_dir && base_dir[0] ? base_dir : ".", stem};
    return load_text(out, yaml ? yaml : "", &src, overrides, noverrides, err);
}

/* The single-scene loaders return the one view there is; a scene with
 * several views needs the views loaders. */
static orr_status take_single(orr_scene *s, const orr_scene_views *views, orr_error *err)
{
    if (views->n == 1) {
        *s = views->view[0];
        return ORR_OK;
    }
    char names[ORR_ERROR_MSG_MAX / 2] = "";
    for (int i = 0; i < views->n; i++) {
        size_t len = strlen(names);
        snprintf(names + len, sizeof names - len, "%s%s", i ? ", " : "", views->name[i]);
    }
    return orr_fail(err, ORR_ERR_USAGE,
                    "%s: the scene has %d views (%s) but was loaded as a single scene; load it with "
                    "orr_scene_load_views to render every view",
                    views->view[0].path, views->n, names);
}

/* A failed load leaves s with the defaults and its name, as it always has. */
static void start_single(orr_scene *s, const char *path)
{
    orr_scene_defaults(s);
    if (path && strlen(path) < sizeof s->path)
        snprintf(s->path, sizeof s->path, "%s", path);
}

orr_status orr_scene_load(orr_scene *s, const char *path, const char *const *overrides, int noverrides,
                          orr_error *err)
{
    start_single(s, path);
    orr_scene_views *views = orr_malloc(sizeof *views, "the views of a scene", err);
    if (!views)
        return ORR_ERR_NOMEM;
    orr_status st = orr_scene_load_views(views, path, overrides, noverrides, err);
    if (st == ORR_OK)
        st = take_single(s, views, err);
    free(views);
    return st;
}

orr_status orr_scene_load_string(orr_scene *s, const char *yaml, const char *origin, const char *base_dir,
                                 const char *const *overrides, int noverrides, orr_error *err)
{
    start_single(s, origin);
    orr_scene_views *views = orr_malloc(sizeof *views, "the views of a scene", err);
    if (!views)
        return ORR_ERR_NOMEM;
    orr_status st = orr_scene_load_views_string(views, yaml, origin, base_dir, overrides, noverrides, err);
    if (st == ORR_OK)
        st = take_single(s, views, err);
    free(views);
    return st;
}

int orr_scene_look_target(const orr_scene *s, orr_vec3 *target)
{
    const orr_camera_path *p = &s->camera_path;
    if (s->has_path && (p->kind == ORR_PATH_ORBIT || p->kind == ORR_PATH_INSPIRAL)) {
        *target = p->centre;
        return 1;
    }
    if (s->has_path && p->kind == ORR_PATH_LINE && p->has_look_at) {
        *target = p->look_at;
        return 1;
    }
    if (!s->has_path && s->has_look_at) {
        *target = s->camera_look_at;
        return 1;
    }
    return 0;
}

orr_status orr_scene_static_camera(const orr_scene *s, orr_camera *cam, orr_error *err)
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
