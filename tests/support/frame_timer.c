/* See frame_timer.h. */
#include "frame_timer.h"

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "core/owned.h"
#include "render/render.h"
#include "scene/scene.h"
#include "source/arrays.h"
#include "clocks.h"

typedef struct clock_mark {
    double start, splat_end, cpu_start, cpu_end;
} clock_mark;

static void mark_progress(void *user, uint64_t done, int64_t total)
{
    (void)done, (void)total;
    ((clock_mark *)user)->splat_end = wall_seconds();
    ((clock_mark *)user)->cpu_end = cpu_seconds();
}

double frame_timer_best(const char *yaml, const orr_particle_arrays *a, int repeats, double *cpu)
{
    orr_scene *s = calloc(1, sizeof *s);
    orr_error err = {0};
    if (!s || orr_scene_load_string(s, yaml, "bench.yaml", ".", NULL, 0, &err)) {
        fprintf(stderr, "%s\n", err.msg);
        exit(1);
    }
    if (orr_owned_set(&s->output.dir, "/tmp", &err)) {
        fprintf(stderr, "%s\n", err.msg);
        exit(1);
    }
    s->output.write_png = 0;
    double best = 1e300;
    for (int r = 0; r < repeats; r++) {
        orr_source *src;
        if (orr_arrays_source_open(a, "bench arrays", (size_t)s->input.chunk_size, 0, &src, &err)) {
            fprintf(stderr, "%s\n", err.msg);
            exit(1);
        }
        orr_frame_input in = {.time = orr_frame_at(0, 1, 25, 0, 0), .source = src};
        orr_render_report rep;
        const orr_scene *list[1] = {s};
        clock_mark m = {wall_seconds(), 0, cpu_seconds(), 0};
        if (orr_render_frame(list, 1, &in, &rep, mark_progress, &m, &err)) {
            fprintf(stderr, "%s\n", err.msg);
            exit(1);
        }
        orr_source_close(src);
        if (m.splat_end - m.start < best) {
            best = m.splat_end - m.start;
            *cpu = m.cpu_end - m.cpu_start;
        }
    }
    orr_scene_free(s);
    free(s);
    return best;
}
