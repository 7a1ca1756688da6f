/* A picture's metadata (encode/image_out.h's orr_image_meta): checked,
 * and as the text every writer stores. Apart from the writers, so that the
 * OpenImageIO module (oiio.cpp) has its own copy without them. */
#include "encode/image_out.h"

#include <ctype.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include "core/numbers.h"

/* ---- metadata ------------------------------------------------------------ */

static int has_control_char(const char *s)
{
    for (; *s; s++)
        if ((unsigned char)*s < 0x20 || *s == 0x7f)
            return 1;
    return 0;
}

static int valid_key(const char *k)
{
    size_t len = strlen(k);
    if (len == 0 || len > ORR_IMAGE_META_KEY_MAX)
        return 0;
    for (; *k; k++)
        if (!isalnum((unsigned char)*k) && *k != '_' && *k != '.' && *k != '-')
            return 0;
    return 1;
}

static orr_status check_string(const char *s, const char *what, const char *path, orr_error *err)
{
    if (s && has_control_char(s))
        return orr_fail(err, ORR_ERR_USAGE, "%s: metadata %s contains a control character (newline, tab, ...)",
                        path, what);
    return ORR_OK;
}

orr_status orr_image_meta_check(const orr_image_meta *meta, const char *path, orr_error *err)
{
    if (!path)
        path = "image output";
    if (!meta)
        return ORR_OK;
    orr_status st;
    if ((st = check_string(meta->scene, "scene", path, err)) != ORR_OK ||
        (st = check_string(meta->projection, "projection", path, err)) != ORR_OK ||
        (st = check_string(meta->software, "software", path, err)) != ORR_OK)
        return st;
    if (meta->has_frame && (meta->frame < INT_MIN || meta->frame > INT_MAX))
        return orr_fail(err, ORR_ERR_USAGE, "%s: frame number %ld is out of range", path, meta->frame);
    if (meta->has_screen_window &&
        !(meta->screen_window_width > 0 && meta->screen_window_width < 1e30 &&
          fabs(meta->screen_window_center[0]) < 1e30 && fabs(meta->screen_window_center[1]) < 1e30))
        return orr_fail(err, ORR_ERR_USAGE, "%s: screen window width %g, centre (%g, %g): not a usable lens", path,
                        meta->screen_window_width, meta->screen_window_center[0], meta->screen_window_center[1]);
    if (meta->nextra < 0 || meta->nextra > ORR_IMAGE_META_MAX_EXTRA)
        return orr_fail(err, ORR_ERR_USAGE, "%s: %d metadata pairs (0 to %d allowed)", path, meta->nextra,
                        ORR_IMAGE_META_MAX_EXTRA);
    for (int i = 0; i < meta->nextra; i++) {
        const char *k = meta->extra_key[i], *v = meta->extra_value[i];
        if (!k || !valid_key(k))
            return orr_fail(err, ORR_ERR_USAGE,
                            "%s: metadata key \"%.80s\" must be 1 to %d letters, digits, '_', '.' or '-'", path,
                            k ? k : "", ORR_IMAGE_META_KEY_MAX);
        if (!v)
            return orr_fail(err, ORR_ERR_USAGE, "%s: metadata key %s has no value", path, k);
        if ((st = check_string(v, k, path, err)) != ORR_OK)
            return st;
    }
    return ORR_OK;
}

const char *orr_image_meta_software(const orr_image_meta *meta)
{
    if (meta && meta->software && meta->software[0])
        return meta->software;
    return "orrery " ORRERY_VERSION;
}

/* Shortest decimal form of v: "%.15g", or "%.17g" when that is needed to
 * read back the same double. */
static void format_double(double v, char *buf, size_t size)
{
    orr_snprintf(buf, size, "%.15g", v);
    if (isfinite(v) && orr_strtod(buf, NULL) != v)
        orr_snprintf(buf, size, "%.17g", v);
}

/* Appends to a text being built, counting what would not fit. */
typedef struct text_out {
    char *buf;
    size_t size, len;
} text_out;

static void put(text_out *t, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static void put(text_out *t, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    size_t room = t->len < t->size ? t->size - t->len : 0;
    int n = vsnprintf(room ? t->buf + t->len : NULL, room, fmt, ap);
    va_end(ap);
    if (n > 0)
        t->len += (size_t)n;
}

size_t orr_image_meta_text(const orr_image_meta *meta, char *buf, size_t size)
{
    text_out t = {buf, buf ? size : 0, 0};
    if (t.size)
        buf[0] = '\0';
    put(&t, "software=%s", orr_image_meta_software(meta));
    if (!meta)
        return t.len;
    char a[32], b[32], c[32], d[32];
    if (meta->scene && meta->scene[0])
        put(&t, "\nscene=%s", meta->scene);
    if (meta->has_frame)
        put(&t, "\nframe=%ld", meta->frame);
    if (meta->has_time) {
        format_double(meta->time, a, sizeof a);
        put(&t, "\ntime=%s", a);
    }
    if (meta->projection && meta->projection[0])
        put(&t, "\nprojection=%s", meta->projection);
    if (meta->has_camera) {
        format_double(meta->cam_pos[0], a, sizeof a);
        format_double(meta->cam_pos[1], b, sizeof b);
        format_double(meta->cam_pos[2], c, sizeof c);
        put(&t, "\ncamera.position=%s %s %s", a, b, c);
        format_double(meta->cam_quat[0], a, sizeof a);
        format_double(meta->cam_quat[1], b, sizeof b);
        format_double(meta->cam_quat[2], c, sizeof c);
        format_double(meta->cam_quat[3], d, sizeof d);
        put(&t, "\ncamera.quaternion=%s %s %s %s", a, b, c, d);
    }
    for (int i = 0; i < meta->nextra && i < ORR_IMAGE_META_MAX_EXTRA; i++)
        if (meta->extra_key[i] && meta->extra_value[i])
            put(&t, "\n%s=%s", meta->extra_key[i], meta->extra_value[i]);
    return t.len;
}
