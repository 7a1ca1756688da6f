#include "scene/scene_path.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "scene/scene_value.h"

/* ---- camera.path.keyframes ---- */

static orr_status get_vec3(const scene_at *at, const yt_node *n, orr_vec3 *v)
{
    double d[3];
    orr_status st = scene_get_numbers(at, n, d, 3, "[x, y, z]");
    if (!st)
        *v = orr_v3(d[0], d[1], d[2]);
    return st;
}

#define KEYFRAME_KEYS "frame, position, look_at | direction | quaternion, up, roll"

/* Reads one keyframe mapping into spec; `seen` records which keys it had. */
enum { SEEN_FRAME = 1, SEEN_POSITION = 2, SEEN_LOOK_AT = 4, SEEN_DIRECTION = 8, SEEN_QUATERNION = 16,
       SEEN_UP = 32, SEEN_ROLL = 64 };

static orr_status bind_keyframe_entry(const scene_at *at, const yt_entry *e, orr_keyframe_spec *spec, unsigned *seen)
{
    scene_at c = scene_child_at(at, e);
    const yt_node *v = e->value;
    if (strcmp(e->key, "frame") == 0) {
        *seen |= SEEN_FRAME;
        return scene_get_number(&c, v, &spec->frame);
    }
    if (strcmp(e->key, "position") == 0) {
        *seen |= SEEN_POSITION;
        return get_vec3(&c, v, &spec->position);
    }
    if (strcmp(e->key, "look_at") == 0 || strcmp(e->key, "direction") == 0) {
        const int look = e->key[0] == 'l';
        *seen |= look ? SEEN_LOOK_AT : SEEN_DIRECTION;
        spec->aim = look ? ORR_AIM_LOOK_AT : ORR_AIM_DIRECTION;
        return get_vec3(&c, v, &spec->look);
    }
    if (strcmp(e->key, "quaternion") == 0) {
        double q[4];
        *seen |= SEEN_QUATERNION;
        spec->aim = ORR_AIM_QUATERNION;
        orr_status st = scene_get_numbers(&c, v, q, 4, "[w, x, y, z]");
        spec->quaternion = (orr_quat){q[0], q[1], q[2], q[3]};
        return st;
    }
    if (strcmp(e->key, "up") == 0) {
        *seen |= SEEN_UP;
        spec->has_up = 1;
        return get_vec3(&c, v, &spec->up);
    }
    if (strcmp(e->key, "roll") == 0) {
        *seen |= SEEN_ROLL;
        return scene_get_number(&c, v, &spec->roll);
    }
    return scene_fail_at(at->err, at->origin, c.line, "%s: unknown key '%s' (known: %s)", at->path, e->key,
                         KEYFRAME_KEYS);
}

static int count_bits(unsigned v)
{
    int n = 0;
    for (; v; v &= v - 1)
        n++;
    return n;
}

static orr_status bind_keyframe(const scene_at *at, const yt_node *n, orr_keyframe *key)
{
    char buf[96];
    if (n->kind != YT_MAPPING)
        return scene_fail_at(at->err, at->origin, at->line, "%s: expected a mapping of %s, got %s", at->path,
                             KEYFRAME_KEYS, yt_describe(n, buf, sizeof buf));
    orr_keyframe_spec spec;
    memset(&spec, 0, sizeof spec);
    unsigned seen = 0;
    for (size_t i = 0; i < n->n; i++) {
        orr_status st = bind_keyframe_entry(at, &n->entries[i], &spec, &seen);
        if (st)
            return st;
    }
    if (!(seen & SEEN_FRAME) || !(seen & SEEN_POSITION))
        return scene_fail_at(at->err, at->origin, at->line, "%s: a keyframe needs %s", at->path,
                             !(seen & SEEN_FRAME) ? "a frame" : "a position");
    if (count_bits(seen & (SEEN_LOOK_AT | SEEN_DIRECTION | SEEN_QUATERNION)) != 1)
        return scene_fail_at(at->err, at->origin, at->line,
                             "%s: give exactly one of look_at, direction, quaternion (the keyframe's orientation)",
                             at->path);
    if ((seen & SEEN_QUATERNION) && (seen & (SEEN_UP | SEEN_ROLL)))
        return scene_fail_at(at->err, at->origin, at->line, "%s: up and roll do not apply to a quaternion",
                             at->path);
    orr_status st = orr_keyframe_from_spec(&spec, key, at->err);
    if (st) {
        char prefix[ORR_PATH_MAX + 200];
        scene_loc_prefix(at->origin, at->line, prefix, sizeof prefix);
        return orr_fail_prefix(at->err, "%s%s: ", prefix, at->path);
    }
    return ORR_OK;
}

orr_status scene_bind_keyframes(orr_scene *s, const char *origin, int line, const char *path, const yt_node *n,
                                orr_error *err)
{
    char buf[96];
    if (n->kind != YT_SEQUENCE || n->n < 2 || n->n > ORR_PATH_KEYFRAMES_MAX)
        return scene_fail_at(err, origin, line, "%s: expected a list of 2 to %d keyframes (%s), got %s", path,
                             ORR_PATH_KEYFRAMES_MAX, KEYFRAME_KEYS, yt_describe(n, buf, sizeof buf));
    orr_camera_path *p = &s->camera.path;
    for (size_t i = 0; i < n->n; i++) {
        scene_at at = {n->items[i]->origin, n->items[i]->line ? n->items[i]->line : line, "", err};
        snprintf(at.path, sizeof at.path, "%.100s[%zu]", path, i);
        orr_status st = bind_keyframe(&at, n->items[i], &p->keys[i]);
        if (st)
            return st;
        if (i > 0 && !(p->keys[i].frame > p->keys[i - 1].frame))
            return scene_fail_at(err, at.origin, at.line,
                                 "%s.frame: %g is not after the previous keyframe's frame %g; keyframes must be in "
                                 "increasing frame order",
                                 at.path, p->keys[i].frame, p->keys[i - 1].frame);
    }
    p->nkeys = (int)n->n;
    return ORR_OK;
}

/* ---- checks across keys ---- */

#define COUNT(a) (sizeof(a) / sizeof((a)[0]))

/* Every camera.path.* key but kind, and the kinds that take it. */
static const struct {
    const char *key;
    unsigned kinds; /* bit orr_path_kind */
} PATH_KEYS[] = {
#define KINDS(a) (1u << ORR_PATH_##a)
    {"camera.path.keyframes", KINDS(KEYFRAMES)},
    {"camera.path.file", KINDS(KEYFRAMES)},
    {"camera.path.interpolation", KINDS(KEYFRAMES)},
    {"camera.path.orientation", KINDS(KEYFRAMES)},
    {"camera.path.ease", KINDS(KEYFRAMES) | KINDS(ORBIT) | KINDS(LINE) | KINDS(INSPIRAL) | KINDS(ROTATE)},
    {"camera.path.centre", KINDS(ORBIT)},
    {"camera.path.radius", KINDS(ORBIT)},
    {"camera.path.start", KINDS(ORBIT)},
    {"camera.path.target", KINDS(INSPIRAL)},
    {"camera.path.r0", KINDS(INSPIRAL)},
    {"camera.path.r1", KINDS(INSPIRAL)},
    {"camera.path.radial", KINDS(INSPIRAL)},
    {"camera.path.axis", KINDS(ORBIT) | KINDS(INSPIRAL) | KINDS(ROTATE)},
    {"camera.path.turns", KINDS(ORBIT) | KINDS(INSPIRAL)},
    {"camera.path.start_angle", KINDS(ORBIT) | KINDS(INSPIRAL)},
    {"camera.path.from", KINDS(LINE)},
    {"camera.path.to", KINDS(LINE)},
    {"camera.path.look_at", KINDS(LINE)},
    {"camera.path.up", KINDS(LINE)},
    {"camera.path.angle", KINDS(ROTATE)},
#undef KINDS
};

/* The keys a path takes the place of. */
static const char *const PLACEMENT_KEYS[] = {"camera.position", "camera.look_at", "camera.direction",
                                             "camera.quaternion", "camera.up", "camera.roll"};

/* The keys each kind cannot do without (beyond its defaults). */
static const char *const *required_keys(orr_path_kind kind)
{
    static const char *const orbit[] = {NULL};
    static const char *const line[] = {"camera.path.from", "camera.path.to", NULL};
    static const char *const inspiral[] = {"camera.path.r0", "camera.path.r1", NULL};
    static const char *const rotate[] = {"camera.path.angle", NULL};
    switch (kind) {
    case ORR_PATH_LINE: return line;
    case ORR_PATH_INSPIRAL: return inspiral;
    case ORR_PATH_ROTATE: return rotate;
    default: return orbit;
    }
}

static orr_status check_without_path(const orr_scene *s, const scene_marks *m, orr_error *err)
{
    for (size_t i = 0; i < COUNT(PATH_KEYS); i++)
        if (scene_mark(m, PATH_KEYS[i].key))
            return scene_fail_key(s, m, PATH_KEYS[i].key, err,
                                  "%s needs camera.path.kind (keyframes, orbit, line, inspiral or rotate)",
                                  PATH_KEYS[i].key);
    return ORR_OK;
}

static orr_status check_key_kinds(const orr_scene *s, const scene_marks *m, orr_error *err)
{
    const orr_path_kind kind = s->camera.path.kind;
    for (size_t i = 0; i < COUNT(PATH_KEYS); i++) {
        if (!scene_mark(m, PATH_KEYS[i].key) || (PATH_KEYS[i].kinds & (1u << kind)))
            continue;
        char takes[512] = "";
        for (size_t j = 0; j < COUNT(PATH_KEYS); j++)
            if (PATH_KEYS[j].kinds & (1u << kind)) {
                strncat(takes, takes[0] ? ", " : "", sizeof takes - strlen(takes) - 1);
                strncat(takes, PATH_KEYS[j].key + strlen("camera.path."), sizeof takes - strlen(takes) - 1);
            }
        return scene_fail_key(s, m, PATH_KEYS[i].key, err,
                              "%s does not apply to camera.path.kind: %s (which takes: %s)", PATH_KEYS[i].key,
                              orr_path_kind_name(kind), takes);
    }
    for (const char *const *k = required_keys(kind); *k; k++)
        if (!scene_mark(m, *k))
            return scene_fail_key(s, m, "camera.path.kind", err, "camera.path.kind: %s needs %s",
                                  orr_path_kind_name(kind), *k);
    return ORR_OK;
}

static orr_status check_placement(const orr_scene *s, const scene_marks *m, orr_error *err)
{
    if (s->observer.has_id)
        return scene_fail_key(s, m, "camera.path.kind", err,
                              "camera.path.kind and observer.id are both set: the observer particle places the "
                              "camera, so it cannot also follow a path");
    if (s->camera.path.kind == ORR_PATH_ROTATE)
        return ORR_OK; /* its start is the scene's own camera */
    for (size_t i = 0; i < COUNT(PLACEMENT_KEYS); i++)
        if (scene_mark(m, PLACEMENT_KEYS[i]))
            return scene_fail_key(s, m, PLACEMENT_KEYS[i], err,
                                  "%s is not allowed with camera.path.kind: %s: the path places and orients the "
                                  "camera in every frame",
                                  PLACEMENT_KEYS[i], orr_path_kind_name(s->camera.path.kind));
    return ORR_OK;
}

static orr_status read_keyframes(orr_scene *s, const scene_marks *m, orr_error *err)
{
    orr_camera_path *p = &s->camera.path;
    const int from_list = scene_mark(m, "camera.path.keyframes") != NULL, from_file = s->camera.path_file != NULL;
    if (from_list && from_file)
        return scene_fail_key(s, m, "camera.path.file", err,
                              "camera.path.keyframes and camera.path.file are both set; give the keyframes one way");
    if (!from_list && !from_file)
        return scene_fail_key(s, m, "camera.path.kind", err,
                              "camera.path.kind: keyframes needs camera.path.keyframes (a list) or camera.path.file "
                              "(a CSV file)");
    if (from_file && orr_path_read_csv(s->camera.path_file, p->keys, ORR_PATH_KEYFRAMES_MAX, &p->nkeys, err))
        return orr_fail_prefix(err, "camera.path.file: ");
    return ORR_OK;
}

/* The orbit's plane: from a start point (its in-plane direction, radius and
 * height above the centre) or from the axis alone. */
static orr_status complete_orbit(orr_scene *s, const scene_marks *m, orr_error *err)
{
    orr_camera_path *p = &s->camera.path;
    if (!s->camera.has_path_start) {
        if (!scene_mark(m, "camera.path.radius"))
            return scene_fail_key(s, m, "camera.path.kind", err,
                                  "camera.path.kind: orbit needs camera.path.radius or camera.path.start");
        return ORR_OK;
    }
    static const char *const excluded[] = {"camera.path.radius", "camera.path.start_angle"};
    for (size_t i = 0; i < COUNT(excluded); i++)
        if (scene_mark(m, excluded[i]))
            return scene_fail_key(s, m, excluded[i], err,
                                  "%s and camera.path.start are both set; the start point fixes the orbit's "
                                  "radius and starting angle",
                                  excluded[i]);
    const orr_vec3 axis = orr_v3_normalize(p->axis), v = orr_v3_sub(s->camera.path_start, p->centre);
    p->height = orr_v3_dot(v, axis);
    const orr_vec3 in_plane = orr_v3_sub(v, orr_v3_scale(axis, p->height));
    p->radius = orr_v3_norm(in_plane);
    if (!(p->radius > 1e-12 * fmax(1.0, orr_v3_norm(v))))
        return scene_fail_key(s, m, "camera.path.start", err,
                              "camera.path.start: is on the orbit's axis through camera.path.centre, so it gives "
                              "no radius");
    p->ref = orr_v3_scale(in_plane, 1.0 / p->radius);
    return ORR_OK;
}

static orr_status complete_path(orr_scene *s, const scene_marks *m, orr_error *err)
{
    orr_camera_path *p = &s->camera.path;
    orr_status st = ORR_OK;
    if (!(orr_v3_norm(p->axis) > 0))
        return scene_fail_key(s, m, "camera.path.axis", err, "camera.path.axis: must not be [0, 0, 0]");
    switch (p->kind) {
    case ORR_PATH_KEYFRAMES: st = read_keyframes(s, m, err); break;
    case ORR_PATH_ORBIT:
        if (!(st = orr_path_plane_ref(p->axis, &p->ref, err)))
            st = complete_orbit(s, m, err);
        break;
    case ORR_PATH_INSPIRAL: st = orr_path_plane_ref(p->axis, &p->ref, err); break;
    case ORR_PATH_ROTATE:
        if (orr_scene_static_camera(s, &p->start, err))
            return orr_fail_prefix(err, "%s: camera.path.kind: rotate starts from the scene's camera: ", s->path);
        break;
    case ORR_PATH_LINE: break;
    }
    if (st)
        return st;
    if (orr_path_check(p, err))
        return orr_fail_prefix(err, "%s: ", s->path);
    return ORR_OK;
}

orr_status scene_check_path(orr_scene *s, const scene_marks *m, orr_error *err)
{
    if (!s->camera.has_path)
        return check_without_path(s, m, err);
    orr_status st = check_placement(s, m, err);
    if (!st)
        st = check_key_kinds(s, m, err);
    if (!st)
        st = complete_path(s, m, err);
    return st;
}
