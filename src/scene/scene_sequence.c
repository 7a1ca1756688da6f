#include "scene/scene_sequence.h"

#include <stdio.h>
#include <string.h>

#include "scene/scene_bind.h"

int orr_scene_has_sequence(const orr_scene *s) { return orr_input_has_sequence(&s->input); }

/* Whether the scene's shutter moves particles by their velocities (so the
 * renderer must read vx, vy, vz): a shutter, and simulation time that
 * passes between frames: animation.frame_interval, a sequence's snapshots,
 * or an in-situ run's animation.time. (A single snapshot's particles stand
 * still, and only the camera moves.) pass/motion_blur.h draws the
 * streaks. */
int orr_scene_blur_moves_particles(const orr_scene *s)
{
    if (!(s->animation.shutter > 0))
        return 0;
    if (s->animation.has_frame_interval)
        return s->animation.frame_interval > 0;
    /* A single snapshot's particles stand still from frame to frame, so
     * they do not move while the shutter is open either. */
    if (orr_scene_has_sequence(s))
        return 1;
    return s->input.insitu && s->animation.has_time && s->animation.time[0] != s->animation.time[1];
}

const char *orr_scene_sequence_file(const orr_scene *s, int i) { return orr_sequence_file(&s->input.sequence, i); }

/* Appends one path, resolved as bind_text resolves input.file: relative to
 * the scene's folder when it comes from the scene file (line > 0), as typed
 * when it comes from --set. */
static orr_status append_path(orr_scene *s, size_t *used, const char *origin, int line, const char *item_path,
                              const char *text, orr_error *err)
{
    size_t room = sizeof s->input.sequence.files - *used;
    int len;
    if (line > 0 && text[0] != '/' && strcmp(s->dir, ".") != 0)
        len = snprintf(s->input.sequence.files + *used, room, "%s/%s", s->dir, text);
    else
        len = snprintf(s->input.sequence.files + *used, room, "%s", text);
    if (len < 0 || (size_t)len >= room)
        return scene_fail_at(err, origin, line,
                             "%s: the list's paths take more than %d bytes together; use input.sequence.pattern",
                             item_path, ORR_SEQ_FILES_BYTES);
    *used += (size_t)len + 1;
    return ORR_OK;
}

orr_status scene_bind_sequence_files(orr_scene *s, const char *origin, int line, const char *path, const yt_node *n,
                                     orr_error *err)
{
    char got[96];
    if (n->kind != YT_SEQUENCE || n->n < 2 || n->n > ORR_SEQ_FILES_MAX)
        return scene_fail_at(err, origin, line, "%s: expected a list of 2 to %d snapshot files, got %s", path,
                             ORR_SEQ_FILES_MAX, yt_describe(n, got, sizeof got));
    size_t used = 0;
    for (size_t i = 0; i < n->n; i++) {
        const yt_node *item = n->items[i];
        const int item_line = item->line ? item->line : line;
        char item_path[160];
        snprintf(item_path, sizeof item_path, "%.100s[%zu]", path, i);
        if (item->kind != YT_SCALAR || yt_is_null(item) || !item->text[0])
            return scene_fail_at(err, item->origin, item_line, "%s: expected a file path, got %s", item_path,
                                 yt_describe(item, got, sizeof got));
        orr_status st = append_path(s, &used, item->origin, item_line, item_path, item->text, err);
        if (st)
            return st;
    }
    s->input.sequence.nfiles = (int)n->n;
    return ORR_OK;
}
