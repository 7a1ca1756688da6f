#include "scene/scene_views.h"

#include <stdio.h>
#include <string.h>

#include "core/owned.h"
#include "scene/scene_bind.h"
#include "scene/scene_check.h"

/* An empty `views:` (null, or every view commented out) is no views, as an
 * empty section is no section. */
static int no_views(const yt_node *views)
{
    return !views || yt_is_null(views) || (views->kind == YT_MAPPING && views->n == 0);
}

/* "dome, panorama" for messages. */
static void list_views(const yt_node *views, char *buf, size_t size)
{
    buf[0] = '\0';
    for (size_t i = 0; views && views->kind == YT_MAPPING && i < views->n; i++) {
        size_t len = strlen(buf);
        if (len + 1 < size)
            snprintf(buf + len, size - len, "%s%s", i ? ", " : "", views->entries[i].key);
    }
}

orr_status scene_views_check_override(const yt_node *root, const char *key, const char *origin,
                                      orr_error *err)
{
    if (strncmp(key, "views.", 6) != 0)
        return ORR_OK;
    const char *name = key + 6, *dot = strchr(name, '.');
    if (!dot)
        return ORR_OK; /* views.NAME=...: the whole view */
    const yt_entry *views = yt_find(root, "views");
    for (size_t i = 0; views && views->value->kind == YT_MAPPING && i < views->value->n; i++) {
        const char *have = views->value->entries[i].key;
        if (strlen(have) == (size_t)(dot - name) && strncmp(have, name, (size_t)(dot - name)) == 0)
            return ORR_OK;
    }
    char names[ORR_ERROR_MSG_MAX / 2];
    list_views(views ? views->value : NULL, names, sizeof names);
    return orr_fail(err, ORR_ERR_USAGE, "%s: no view '%.*s' in the scene (%s%s)", origin, (int)(dot - name), name,
                    names[0] ? "its views: " : "it has no views", names);
}

/* ---- checking the views mapping ---- */

static int valid_view_name(const char *name)
{
    size_t len = strlen(name);
    return len > 0 && len < ORR_NAME_MAX &&
           strspn(name, "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789-_") == len;
}

/* A view's mapping is merged before binding, so the binder would not see a
 * key given twice there: the second would silently win. */
static orr_status check_duplicates(const yt_node *map, const char *prefix, orr_error *err)
{
    for (size_t i = 0; i < map->n; i++) {
        const yt_entry *e = &map->entries[i];
        for (size_t j = 0; j < i; j++)
            if (strcmp(map->entries[j].key, e->key) == 0)
                return scene_fail_at(err, e->origin, e->line, "duplicate key '%s.%s' (first set at line %d)", prefix,
                               e->key, map->entries[j].line);
        if (e->value->kind != YT_MAPPING)
            continue;
        char path[256];
        snprintf(path, sizeof path, "%s.%s", prefix, e->key);
        orr_status st = check_duplicates(e->value, path, err);
        if (st != ORR_OK)
            return st;
    }
    return ORR_OK;
}

/* One view: a good name, a mapping (or nothing), no keys the views must share. */
static orr_status check_view(const yt_node *views, size_t i, orr_error *err)
{
    static const char *const shared[] = {"input", "observer", "animation", "views"};
    const yt_entry *v = &views->entries[i];
    char got[96];
    if (!valid_view_name(v->key))
        return scene_fail_at(err, v->origin, v->line,
                       "views: '%s' is not a view name (letters, digits, '-' and '_', at most %d characters)", v->key,
                       ORR_NAME_MAX - 1);
    for (size_t j = 0; j < i; j++)
        if (strcmp(views->entries[j].key, v->key) == 0)
            return scene_fail_at(err, v->origin, v->line, "duplicate view 'views.%s' (first set at line %d)", v->key,
                           views->entries[j].line);
    if (yt_is_null(v->value))
        return ORR_OK; /* the base scene as it is */
    if (v->value->kind != YT_MAPPING)
        return scene_fail_at(err, v->origin, v->line, "views.%s: expected a mapping of scene keys, got %s", v->key,
                       yt_describe(v->value, got, sizeof got));
    for (size_t k = 0; k < sizeof shared / sizeof shared[0]; k++) {
        const yt_entry *e = yt_find(v->value, shared[k]);
        if (e)
            return scene_fail_at(err, e->origin, e->line,
                           "views.%s.%s: a view may not set %s.*: all views are rendered from one pass over the "
                           "same particles; set it outside views:",
                           v->key, shared[k], shared[k]);
    }
    char prefix[256];
    snprintf(prefix, sizeof prefix, "views.%s", v->key);
    return check_duplicates(v->value, prefix, err);
}

static orr_status check_views(const yt_node *views, const scene_loc *at, orr_error *err)
{
    char got[96];
    if (views->kind != YT_MAPPING)
        return scene_fail_at(err, at->origin, at->line, "views: expected a mapping from view names to scene keys, got %s",
                       yt_describe(views, got, sizeof got));
    if (views->n > ORR_SCENE_MAX_VIEWS)
        return scene_fail_at(err, at->origin, at->line, "views: %zu views; a scene has at most %d", views->n,
                       ORR_SCENE_MAX_VIEWS);
    for (size_t i = 0; i < views->n; i++) {
        orr_status st = check_view(views, i, err);
        if (st != ORR_OK)
            return st;
    }
    return ORR_OK;
}

/* ---- building each view ---- */

/* s holds no strings before; after, it is freed by its loader's caller,
 * or by the loader when the load fails. */
static orr_status scene_start(orr_scene *s, const scene_source *src, orr_error *err)
{
    orr_status st = orr_scene_defaults(s, err);
    if (!st)
        st = orr_owned_set(&s->path, src->path, err);
    if (!st)
        st = orr_owned_set(&s->dir, src->dir, err);
    return st;
}

/* Whether the view's own keys set output.name. */
static int view_sets_name(const yt_node *view)
{
    const yt_entry *output = yt_find(view, "output");
    return output && yt_find(output->value, "name");
}

/* The output name rule: a view's own output.name is used as it is; the base
 * scene's gets "-VIEW" appended when there are several views (one name
 * cannot serve them all); without either, "STEM-VIEW". */
static orr_status name_output(orr_scene *s, const yt_entry *view, const scene_source *src, size_t nviews,
                              orr_error *err)
{
    if (view_sets_name(view->value) || (s->output.name[0] && nviews == 1))
        return ORR_OK;
    char name[ORR_NAME_MAX];
    const char *base = s->output.name[0] ? s->output.name : src->stem;
    int len = snprintf(name, sizeof name, "%s-%s", base, view->key);
    if (len < 0 || (size_t)len >= sizeof name)
        return scene_fail_at(err, view->origin, view->line,
                       "views.%s: the output name '%s-%s' is too long (at most %d characters); set output.name in "
                       "the view",
                       view->key, base, view->key, ORR_NAME_MAX - 1);
    memcpy(s->output.name, name, (size_t)len + 1);
    return ORR_OK;
}

/* Adds " (view 'NAME')" to the message: a key of the base scene can be
 * wrong for one view only. */
static orr_status in_view(orr_error *err, orr_status st, const char *name)
{
    if (!err)
        return st;
    char msg[ORR_ERROR_MSG_MAX];
    memcpy(msg, err->msg, sizeof msg);
    return orr_fail(err, st, "%s (view '%s')", msg, name);
}

/* Binds view i: a copy of the base tree with the view's keys merged in. */
static orr_status load_view(orr_scene_views *out, size_t i, const yt_node *base, const yt_node *views,
                            const scene_source *src, orr_error *err)
{
    const yt_entry *view = &views->entries[i];
    orr_scene *s = &out->view[i];
    yt_node *tree = yt_clone(base, err);
    if (!tree)
        return ORR_ERR_NOMEM;
    orr_status st = yt_is_null(view->value) ? ORR_OK : yt_merge(tree, view->value, err);
    orr_status started = scene_start(s, src, err);
    if (st == ORR_OK)
        st = started;
    if (st == ORR_OK)
        st = scene_bind_checked(s, tree, err);
    yt_free(tree);
    if (st == ORR_OK)
        st = name_output(s, view, src, views->n, err);
    if (st != ORR_OK) {
        orr_scene_free(s); /* not counted in out->n yet */
        return st == ORR_ERR_NOMEM ? st : in_view(err, st, view->key);
    }
    snprintf(out->name[i], sizeof out->name[i], "%s", view->key);
    return ORR_OK;
}

/* Two views writing the same file would overwrite each other. Only names
 * are compared: the command line can put every output in one folder. */
static orr_status check_outputs(const orr_scene_views *out, const char *path, orr_error *err)
{
    for (int i = 0; i < out->n; i++)
        for (int j = 0; j < i; j++)
            if (strcmp(out->view[i].output.name, out->view[j].output.name) == 0)
                return orr_fail(err, ORR_ERR_USAGE,
                                "%s: views '%s' and '%s' both write output.name '%s'; give each its own",
                                path, out->name[j], out->name[i], out->view[i].output.name);
    return ORR_OK;
}

static orr_status load_single(orr_scene_views *out, const yt_node *root, const scene_source *src,
                              orr_error *err)
{
    orr_scene *s = &out->view[0];
    orr_status st = scene_start(s, src, err);
    if (st == ORR_OK)
        st = scene_bind_checked(s, root, err);
    if (st == ORR_OK && s->output.name[0] == '\0')
        snprintf(s->output.name, sizeof s->output.name, "%s", src->stem);
    if (st != ORR_OK)
        orr_scene_free(s);
    out->n = st == ORR_OK;
    return st;
}

static orr_status load_views(orr_scene_views *out, const yt_node *base, const yt_node *views, const scene_loc *at,
                             const scene_source *src, orr_error *err)
{
    orr_status st = check_views(views, at, err);
    for (size_t i = 0; st == ORR_OK && i < views->n; i++)
        if ((st = load_view(out, i, base, views, src, err)) == ORR_OK)
            out->n = (int)i + 1;
    if (st == ORR_OK)
        st = check_outputs(out, src->path, err);
    return st;
}

orr_status scene_views_from_tree(orr_scene_views *out, yt_node *root, const scene_source *src, orr_error *err)
{
    memset(out->name, 0, sizeof out->name);
    out->n = 0;
    const yt_entry *e = yt_find(root, "views");
    const scene_loc at = {e ? e->origin : src->path, e ? e->line : 0};
    yt_node *views = yt_detach(root, "views"); /* the base scene is the rest */
    orr_status st = no_views(views) ? load_single(out, root, src, err) : load_views(out, root, views, &at, src, err);
    yt_free(views);
    return st;
}
