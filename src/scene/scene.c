#include "scene/scene.h"

#include <errno.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "scene/scene_bind.h"
#include "scene/ytree.h"

/* Scene files are a few hundred bytes; the cap only stops a wrong path (a
 * snapshot, a device) from being read into memory. */
#define SCENE_FILE_MAX (16u << 20)

void orr_scene_defaults(orr_scene *s)
{
    memset(s, 0, sizeof *s);
    snprintf(s->path, sizeof s->path, "<built-in>");
    snprintf(s->dir, sizeof s->dir, ".");

    snprintf(s->input_format, sizeof s->input_format, "auto");
    s->model_particles = 200000;
    s->model_seed = 1;
    s->model_separation = 780;
    snprintf(s->weight, sizeof s->weight, "mass");
    s->type_mask = 0x3f;
    s->chunk_size = 1048576;
    s->skip_nonfinite = 0;

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
    s->deposit = ORR_DEPOSIT_CIC;

    snprintf(s->out_dir, sizeof s->out_dir, ".");
    s->write_fits = 1;
    s->write_png = 1;
    s->png_bits = 8;
    s->stretch = (orr_stretch){.kind = ORR_STRETCH_LOG, .white = 0, .white_percentile = 99.9, .n = 1000};
    s->colormap = ORR_CMAP_MAGMA;
    snprintf(s->bunit, sizeof s->bunit, "mass/pixel");
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

/* ---- checks across keys ---- */

/* Fails with "origin:line: " of key (or the scene path when the key was not
 * set) before the formatted text. */
static orr_status fail_key(const orr_scene *s, const scene_marks *m, const char *key, orr_error *err,
                           const char *fmt, ...) __attribute__((format(printf, 5, 6)));

static orr_status fail_key(const orr_scene *s, const scene_marks *m, const char *key, orr_error *err,
                           const char *fmt, ...)
{
    char prefix[ORR_ERROR_MSG_MAX];
    char text[ORR_ERROR_MSG_MAX];
    const scene_loc *loc = scene_mark(m, key);
    scene_loc_prefix(loc ? loc->origin : s->path, loc ? loc->line : 0, prefix, sizeof prefix);
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(text, sizeof text, fmt, ap);
    va_end(ap);
    return orr_fail(err, ORR_ERR_USAGE, "%s%s", prefix, text);
}

static orr_status check_input(const orr_scene *s, const scene_marks *m, orr_error *err)
{
    static const char *const model_keys[] = {"input.model.particles", "input.model.seed",
                                             "input.model.separation"};
    const int has_file = s->input_file[0] != '\0', has_model = s->model_name[0] != '\0';
    if (has_file && has_model)
        return fail_key(s, m, "input.model.name", err,
                        "input.file and input.model.name are both set; use one of them");
    if (!has_file && !has_model)
        return orr_fail(err, ORR_ERR_USAGE, "%s: no input: set input.file or input.model.name", s->path);
    for (size_t i = 0; has_file && i < sizeof model_keys / sizeof model_keys[0]; i++)
        if (scene_mark(m, model_keys[i]))
            return fail_key(s, m, model_keys[i], err, "%s applies to input.model.name, but the input is input.file",
                            model_keys[i]);
    return ORR_OK;
}

static int is_zero(orr_vec3 v) { return v.x == 0 && v.y == 0 && v.z == 0; }

/* True when a and b point along the same line (or either is zero). */
static int parallel(orr_vec3 a, orr_vec3 b)
{
    return orr_v3_norm(orr_v3_cross(a, b)) <= 1e-12 * orr_v3_norm(a) * orr_v3_norm(b);
}

static orr_status check_orientation_count(const orr_scene *s, const scene_marks *m, orr_error *err)
{
    static const char *const keys[] = {"camera.look_at", "camera.direction", "camera.quaternion"};
    const char *first = NULL;
    for (int i = 0; i < 3; i++) {
        if (!scene_mark(m, keys[i]))
            continue;
        if (first)
            return fail_key(s, m, keys[i], err,
                            "%s and %s are both set; use at most one of camera.look_at, camera.direction, "
                            "camera.quaternion",
                            first, keys[i]);
        first = keys[i];
    }
    return ORR_OK;
}

static orr_status check_camera(orr_scene *s, const scene_marks *m, orr_error *err)
{
    orr_status st = check_orientation_count(s, m, err);
    if (st != ORR_OK)
        return st;
    if (s->has_quaternion) {
        orr_quat q = s->camera_quaternion;
        if (q.w == 0 && q.x == 0 && q.y == 0 && q.z == 0)
            return fail_key(s, m, "camera.quaternion", err,
                            "camera.quaternion: [0, 0, 0, 0] is not a rotation (zero length)");
        /* Users round their quaternions; the renderer wants a unit one. */
        s->camera_quaternion = orr_quat_normalize(q);
    }
    if (s->has_direction && is_zero(s->camera_direction))
        return fail_key(s, m, "camera.direction", err, "camera.direction: must not be [0, 0, 0]");
    if (s->has_up && is_zero(s->camera_up))
        return fail_key(s, m, "camera.up", err, "camera.up: must not be [0, 0, 0]");
    orr_vec3 view = s->has_look_at ? orr_v3_sub(s->camera_look_at, s->camera_position) : s->camera_direction;
    if (s->has_look_at && is_zero(view))
        return fail_key(s, m, "camera.look_at", err,
                        "camera.look_at: equals camera.position, so there is no direction to look in");
    if (s->has_up && (s->has_look_at || s->has_direction) && parallel(view, s->camera_up))
        return fail_key(s, m, "camera.up", err, "camera.up: is parallel to the view direction (%s)",
                        s->has_look_at ? "camera.look_at - camera.position" : "camera.direction");
    return ORR_OK;
}

/* The projection validates its own parameters (image size, width, field of
 * view); a copy keeps the derived fields out of the scene. */
static orr_status check_projection(const orr_scene *s, orr_error *err)
{
    orr_projection copy = s->projection;
    orr_status st = orr_projection_setup(&copy, err);
    if (st != ORR_OK)
        return orr_fail_prefix(err, "%s: ", s->path);
    return ORR_OK;
}

/* ---- loading ---- */

/* The file name without folder and extension: "scenes/face-on.yaml" -> "face-on". */
static void path_stem(const char *path, char *out, size_t size)
{
    const char *slash = strrchr(path, '/');
    const char *base = slash ? slash + 1 : path;
    const char *dot = strrchr(base, '.');
    size_t len = (dot && dot != base) ? (size_t)(dot - base) : strlen(base);
    if (len >= size)
        len = size - 1;
    memcpy(out, base, len);
    out[len] = '\0';
}

/* The folder part of path: "a/b/scene.yaml" -> "a/b", "scene.yaml" -> ".". */
static void path_dir(const char *path, char *out, size_t size)
{
    const char *slash = strrchr(path, '/');
    if (!slash)
        snprintf(out, size, ".");
    else if (slash == path)
        snprintf(out, size, "/");
    else
        snprintf(out, size, "%.*s", (int)(slash - path), path);
}

/* Builds the tree from text and the overrides, binds it and checks it. */
static orr_status load_tree(orr_scene *s, yt_node **root, const char *text, char **origins,
                            const char *const *overrides, int noverrides, orr_error *err)
{
    orr_status st = yt_parse(text, strlen(text), s->path, 1, root, err);
    if (st != ORR_OK)
        return st;
    if (!*root || yt_is_null(*root))
        return orr_fail(err, ORR_ERR_USAGE, "%s: the scene is empty (expected a mapping of keys such as input:)",
                        s->path);
    if ((*root)->kind != YT_MAPPING) {
        char got[96];
        return orr_fail(err, ORR_ERR_USAGE, "%s:%d: the top level of a scene must be a mapping of keys, not %s",
                        s->path, (*root)->line, yt_describe(*root, got, sizeof got));
    }
    for (int i = 0; i < noverrides; i++)
        if ((st = apply_override(*root, overrides[i], origins[i], err)) != ORR_OK)
            return st;
    scene_marks marks;
    if ((st = scene_bind(s, *root, &marks, err)) != ORR_OK)
        return st;
    if ((st = check_input(s, &marks, err)) != ORR_OK || (st = check_camera(s, &marks, err)) != ORR_OK ||
        (st = check_projection(s, err)) != ORR_OK)
        return st;
    return ORR_OK;
}

/* The common part of both loaders; s->path and s->dir are already set. */
static orr_status load_text(orr_scene *s, const char *text, const char *name_from,
                            const char *const *overrides, int noverrides, orr_error *err)
{
    if (noverrides < 0 || (noverrides > 0 && !overrides))
        return orr_fail(err, ORR_ERR_INTERNAL, "%s: bad override list (%d)", s->path, noverrides);
    char **origins = override_origins(overrides, noverrides, err);
    if (!origins)
        return ORR_ERR_NOMEM;
    yt_node *root = NULL;
    orr_status st = load_tree(s, &root, text, origins, overrides, noverrides, err);
    yt_free(root); /* before the origins: its nodes point at them */
    free_origins(origins, noverrides);
    if (st == ORR_OK && s->out_name[0] == '\0') {
        path_stem(name_from ? name_from : "", s->out_name, sizeof s->out_name);
        if (s->out_name[0] == '\0')
            snprintf(s->out_name, sizeof s->out_name, "orrery");
    }
    return st;
}

/* Reads a whole file into a NUL-terminated buffer. */
static orr_status read_file(const char *path, char **out, size_t *out_len, orr_error *err)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return orr_fail(err, ORR_ERR_IO, "%s: cannot open scene file: %s", path, strerror(errno));
    size_t cap = 4096, len = 0;
    char *buf = orr_malloc(cap, "the scene file", err);
    orr_status st = buf ? ORR_OK : ORR_ERR_NOMEM;
    while (st == ORR_OK) {
        if (len + 1 == cap) {
            char *bigger = cap >= SCENE_FILE_MAX ? NULL : realloc(buf, 2 * cap);
            if (!bigger) {
                st = cap >= SCENE_FILE_MAX
                         ? orr_fail(err, ORR_ERR_USAGE, "%s: larger than %u bytes; not a scene file", path,
                                    SCENE_FILE_MAX)
                         : orr_fail(err, ORR_ERR_NOMEM, "%s: out of memory reading the scene file", path);
                break;
            }
            buf = bigger;
            cap *= 2;
        }
        size_t got = fread(buf + len, 1, cap - 1 - len, f);
        len += got;
        if (got == 0 && ferror(f))
            st = orr_fail(err, ORR_ERR_IO, "%s: cannot read scene file: %s", path, strerror(errno));
        else if (got == 0)
            break;
    }
    fclose(f);
    if (st != ORR_OK) {
        free(buf);
        return st;
    }
    buf[len] = '\0';
    *out = buf;
    *out_len = len;
    return ORR_OK;
}

orr_status orr_scene_load(orr_scene *s, const char *path, const char *const *overrides, int noverrides,
                          orr_error *err)
{
    orr_scene_defaults(s);
    if (strlen(path) >= sizeof s->path)
        return orr_fail(err, ORR_ERR_USAGE, "scene file name is too long (%zu characters)", strlen(path));
    snprintf(s->path, sizeof s->path, "%s", path);
    path_dir(path, s->dir, sizeof s->dir);
    char *text = NULL;
    size_t len = 0;
    orr_status st = read_file(path, &text, &len, err);
    if (st != ORR_OK)
        return st;
    if (strlen(text) != len) {
        free(text);
        return orr_fail(err, ORR_ERR_USAGE, "%s: contains a NUL byte; not a text file", path);
    }
    st = load_text(s, text, path, overrides, noverrides, err);
    free(text);
    return st;
}

orr_status orr_scene_load_string(orr_scene *s, const char *yaml, const char *origin, const char *base_dir,
                                 const char *const *overrides, int noverrides, orr_error *err)
{
    orr_scene_defaults(s);
    if (origin && strlen(origin) >= sizeof s->path)
        return orr_fail(err, ORR_ERR_USAGE, "scene name is too long (%zu characters)", strlen(origin));
    if (base_dir && strlen(base_dir) >= sizeof s->dir)
        return orr_fail(err, ORR_ERR_USAGE, "%s: base folder name is too long", origin ? origin : s->path);
    if (origin)
        snprintf(s->path, sizeof s->path, "%s", origin);
    if (base_dir && base_dir[0])
        snprintf(s->dir, sizeof s->dir, "%s", base_dir);
    return load_text(s, yaml ? yaml : "", origin, overrides, noverrides, err);
}
