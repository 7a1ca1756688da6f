#include "scene/scene_value.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "scene/scene_bind.h"
#include "core/numbers.h"

scene_at scene_child_at(const scene_at *at, const yt_entry *e)
{
    scene_at c = *at;
    /* Keys are short; a path that would not fit is cut, only in messages. */
    int len = snprintf(c.path, sizeof c.path, "%.100s.%.50s", at->path, e->key);
    (void)len;
    c.line = e->line ? e->line : at->line;
    return c;
}

orr_status scene_get_number(const scene_at *at, const yt_node *n, double *v)
{
    char *end = NULL;
    if (n->kind == YT_SCALAR && !yt_is_null(n)) {
        *v = orr_strtod(n->text, &end);
        if (end != n->text && *end == '\0' && isfinite(*v))
            return ORR_OK;
    }
    char buf[96];
    return scene_fail_at(at->err, at->origin, at->line, "%s: expected a finite number, got %s", at->path,
                         yt_describe(n, buf, sizeof buf));
}

orr_status scene_get_numbers(const scene_at *at, const yt_node *n, double *v, size_t count, const char *form)
{
    char buf[96];
    if (n->kind != YT_SEQUENCE || n->n != count)
        return scene_fail_at(at->err, at->origin, at->line, "%s: expected a list of %zu numbers%s%s, got %s",
                             at->path, count, form ? " " : "", form ? form : "", yt_describe(n, buf, sizeof buf));
    for (size_t i = 0; i < count; i++) {
        orr_status st = scene_get_number(at, n->items[i], &v[i]);
        if (st)
            return st;
    }
    return ORR_OK;
}
