#include "scene/scene_dome.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "scene/scene_file.h"
#include "scene/ytree.h"

/* ---- the search path ---- */

/* Walks the folders searched for profiles, in order. */
typedef struct folder_iter {
    const char *env;       /* what is left of $ORRERY_DOMES, or NULL */
    const char *scene_dir; /* the scene's folder */
    int stage;             /* 0: $ORRERY_DOMES, 1: ../domes, 2: domes, 3: installed, 4: done */
} folder_iter;

/* Copies the next folder into buf and returns 1; returns -1 for a folder
 * whose name does not fit (skipped), 0 when there are no more. Empty
 * entries of $ORRERY_DOMES ("a::b", a trailing ':') are skipped. */
static int next_folder(folder_iter *it, char *buf, size_t size)
{
    int len = -1;
    while (it->stage == 0 && it->env && *it->env) {
        const char *colon = strchr(it->env, ':');
        size_t n = colon ? (size_t)(colon - it->env) : strlen(it->env);
        const char *entry = it->env;
        it->env = colon ? colon + 1 : entry + n;
        if (n > 0) {
            len = n < size ? snprintf(buf, size, "%.*s", (int)n, entry) : -1;
            return len >= 0 ? 1 : -1;
        }
    }
    if (it->stage == 0)
        it->stage = 1; /* $ORRERY_DOMES is used up */
    switch (it->stage++) {
    case 1: len = snprintf(buf, size, "%s/../domes", it->scene_dir); break;
    case 2: len = snprintf(buf, size, "%s/domes", it->scene_dir); break;
#ifdef ORRERY_DOMES_DIR
    case 3: len = snprintf(buf, size, "%s", ORRERY_DOMES_DIR); break;
#endif
    default: it->stage = 4; return 0;
    }
    return len >= 0 && (size_t)len < size ? 1 : -1;
}

/* Appends ", folder" (or the first folder) to the list of places looked in;
 * folders that do not fit are left out of the message. */
static void note_folder(char *looked, size_t size, const char *folder)
{
    const size_t len = strlen(looked), sep = len ? 2 : 0, add = strlen(folder);
    if (len + sep + add >= size)
        return;
    memcpy(looked + len, ", ", sep);
    memcpy(looked + len + sep, folder, add + 1);
}

/* The path of the first NAME.yaml on the search path, in path (of size size). */
static orr_status find_profile(const orr_scene *s, const scene_marks *m, char *path, size_t size,
                               orr_error *err)
{
    folder_iter it = {getenv("ORRERY_DOMES"), s->dir, 0};
    char folder[ORR_PATH_MAX];
    char looked[ORR_ERROR_MSG_MAX / 2] = "";
    int more;
    while ((more = next_folder(&it, folder, sizeof folder)) != 0) {
        if (more < 0)
            continue; /* a folder name longer than a path can be */
        int len = snprintf(path, size, "%s/%s.yaml", folder, s->camera.dome);
        if (len < 0 || (size_t)len >= size)
            continue; /* cannot name a file there */
        note_folder(looked, sizeof looked, folder);
        FILE *f = fopen(path, "rb");
        if (f) {
            fclose(f);
            return ORR_OK;
        }
        /* Missing is normal (look further); unreadable is worth saying. */
        if (errno != ENOENT && errno != ENOTDIR)
            return scene_fail_key(s, m, "camera.dome", err, "camera.dome: cannot open dome profile %s: %s", path,
                                  strerror(errno));
    }
    return scene_fail_key(s, m, "camera.dome", err,
                          "camera.dome: no dome profile '%s': looked for %s.yaml in %s (folders of profiles can "
                          "be added with the ORRERY_DOMES environment variable)",
                          s->camera.dome, s->camera.dome, looked[0] ? looked : "no folder");
}

/* ---- reading a profile ---- */

static orr_status bind_profile_text(const char *path, const char *text, dome_profile *p, orr_error *err)
{
    yt_node *root = NULL;
    orr_status st = yt_parse(text, strlen(text), path, 1, &root, err);
    if (st == ORR_OK && (!root || yt_is_null(root))) {
        st = orr_fail(err, ORR_ERR_USAGE, "%s: the dome profile is empty (expected keys such as fov:)", path);
    } else if (st == ORR_OK && root->kind != YT_MAPPING) {
        char got[96];
        st = orr_fail(err, ORR_ERR_USAGE, "%s:%d: a dome profile must be a mapping of keys, not %s", path,
                      root->line, yt_describe(root, got, sizeof got));
    } else if (st == ORR_OK) {
        memset(p, 0, sizeof *p);
        st = dome_profile_bind(p, root, err);
    }
    yt_free(root);
    return st;
}

static orr_status load_profile(const char *path, dome_profile *p, orr_error *err)
{
    char *text = NULL;
    orr_status st = scene_read_text(path, "dome profile", &text, err);
    if (st != ORR_OK)
        return st;
    st = bind_profile_text(path, text, p, err);
    free(text);
    return st;
}

/* ---- applying it ---- */

orr_status scene_apply_dome_profile(orr_scene *s, const scene_marks *m, orr_error *err)
{
    if (!s->camera.dome[0])
        return ORR_OK;
    char path[ORR_PATH_MAX];
    dome_profile p;
    orr_status st = find_profile(s, m, path, sizeof path, err);
    if (st == ORR_OK)
        st = load_profile(path, &p, err);
    /* Read and checked for every projection, so that a view switching to
     * the dome finds no surprise; applied only to dome masters, so that a
     * panorama of the same scene keeps its own image size. */
    if (st != ORR_OK || s->projection.kind != ORR_PROJ_DOME)
        return st;
    if (p.has_fov && !scene_mark(m, "camera.dome_fov"))
        s->projection.dome_fov_deg = p.fov;
    if (p.has_tilt && !scene_mark(m, "camera.dome_tilt"))
        s->camera.dome_tilt = p.tilt;
    if (p.has_size && !scene_mark(m, "image.width"))
        s->projection.width = p.size;
    if (p.has_size && !scene_mark(m, "image.height"))
        s->projection.height = p.size;
    return ORR_OK;
}
