#include "scene/scene.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/owned.h"
#include "scene/scene_file.h"
#include "scene/scene_views.h"
#include "scene/ytree.h"

static void animation_defaults(orr_animation_settings *a)
{
    memset(a, 0, sizeof *a);
    a->frames = 1;
    a->fps = 30;
}

orr_status orr_scene_defaults(orr_scene *s, orr_error *err)
{
    memset(s, 0, sizeof *s);
    /* Each stage's defaults live with the stage. */
    orr_input_settings_defaults(&s->input);
    orr_periodic_settings_defaults(&s->periodic);
    orr_camera_settings_defaults(&s->camera);
    orr_projection_defaults(&s->projection);
    orr_observer_settings_defaults(&s->observer);
    orr_stereo_settings_defaults(&s->stereo);
    orr_deposit_settings_defaults(&s->deposit);
    orr_stars_defaults(&s->stars);
    orr_dust_settings_defaults(&s->dust);
    orr_colour_settings_defaults(&s->colour);
    orr_psf_settings_defaults(&s->psf);
    orr_picture_settings_defaults(&s->picture);
    orr_output_settings_defaults(&s->output);
    animation_defaults(&s->animation);
    orr_status st = orr_owned_set(&s->path, "<built-in>", err);
    if (!st)
        st = orr_owned_set(&s->dir, ".", err);
    if (!st)
        st = orr_owned_set(&s->output.dir, ".", err);
    return st;
}

/* ---- the scene's strings ---- */

/* Every owned string of the scene, its own and its stages'. */
#define SCENE_STRINGS (2 + ORR_INPUT_STRINGS + ORR_CAMERA_STRINGS + ORR_DUST_STRINGS + ORR_PSF_STRINGS + \
                       ORR_OUTPUT_STRINGS + ORR_COMPOSE_STRINGS)

static int scene_strings(orr_scene *s, char **fields[SCENE_STRINGS])
{
    int n = 0;
    fields[n++] = &s->path;
    fields[n++] = &s->dir;
    n += orr_input_settings_strings(&s->input, fields + n);
    n += orr_camera_settings_strings(&s->camera, fields + n);
    n += orr_dust_settings_strings(&s->dust, fields + n);
    n += orr_psf_settings_strings(&s->psf, fields + n);
    n += orr_output_settings_strings(&s->output, fields + n);
    n += orr_compose_settings_strings(&s->compose, fields + n);
    return n;
}

void orr_scene_free(orr_scene *s)
{
    char **fields[SCENE_STRINGS];
    orr_owned_free_all(fields, scene_strings(s, fields));
}

orr_status orr_scene_copy(orr_scene *dst, const orr_scene *src, orr_error *err)
{
    char **fields[SCENE_STRINGS];
    return orr_owned_copy(dst, src, sizeof *dst, fields, scene_strings(dst, fields), err);
}

orr_status orr_scene_set_output_dir(orr_scene *s, const char *dir, orr_error *err)
{
    return orr_owned_set(&s->output.dir, dir, err);
}

void orr_scene_views_free(orr_scene_views *views)
{
    for (int i = 0; i < views->n; i++)
        orr_scene_free(&views->view[i]);
    views->n = 0;
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
    if (st != ORR_OK)
        orr_scene_views_free(out); /* the views bound before the failure */
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
static orr_status take_single(orr_scene *s, orr_scene_views *views, orr_error *err)
{
    if (views->n == 1) {
        orr_scene_free(s); /* its defaults */
        *s = views->view[0]; /* moved: the strings are s's now */
        views->n = 0;
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

/* take_single, and the views freed after it (the ones not taken). */
static orr_status take_single_free(orr_scene *s, orr_scene_views *views, orr_error *err)
{
    orr_status st = take_single(s, views, err);
    orr_scene_views_free(views);
    return st;
}

/* A failed load leaves s with the defaults and its name, as it always has. */
static orr_status start_single(orr_scene *s, const char *path, orr_error *err)
{
    orr_status st = orr_scene_defaults(s, err);
    if (!st && path && strlen(path) < ORR_PATH_MAX)
        st = orr_owned_set(&s->path, path, err);
    return st;
}

orr_status orr_scene_load(orr_scene *s, const char *path, const char *const *overrides, int noverrides,
                          orr_error *err)
{
    if (start_single(s, path, err))
        return ORR_ERR_NOMEM;
    orr_scene_views *views = orr_malloc(sizeof *views, "the views of a scene", err);
    if (!views)
        return ORR_ERR_NOMEM;
    orr_status st = orr_scene_load_views(views, path, overrides, noverrides, err);
    if (st == ORR_OK)
        st = take_single_free(s, views, err);
    free(views);
    return st;
}

orr_status orr_scene_load_string(orr_scene *s, const char *yaml, const char *origin, const char *base_dir,
                                 const char *const *overrides, int noverrides, orr_error *err)
{
    if (start_single(s, origin, err))
        return ORR_ERR_NOMEM;
    orr_scene_views *views = orr_malloc(sizeof *views, "the views of a scene", err);
    if (!views)
        return ORR_ERR_NOMEM;
    orr_status st = orr_scene_load_views_string(views, yaml, origin, base_dir, overrides, noverrides, err);
    if (st == ORR_OK)
        st = take_single_free(s, views, err);
    free(views);
    return st;
}

int orr_scene_look_target(const orr_scene *s, orr_vec3 *target)
{
    return orr_camera_settings_look_target(&s->camera, target);
}

orr_status orr_scene_static_camera(const orr_scene *s, orr_camera *cam, orr_error *err)
{
    return orr_camera_settings_static(&s->camera, cam, err);
}
