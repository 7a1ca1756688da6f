/* Runs of frames: frame names, frame times, the frames a job takes, and
 * resumption (complete frames skipped, a truncated one redone). */
#include <fitsio.h>
#include <stdlib.h>
#include <sys/stat.h>
#include <unistd.h>

#include "check.h"
#include "render/animation.h"
#include "scene/scene.h"
#include "tmpdir.h"

static void test_frame_names(void)
{
    char name[64];
    orr_error err = {0};
    CHECK(orr_frame_name("sky", 0, 1, name, sizeof name, &err) == ORR_OK);
    CHECK(strcmp(name, "sky") == 0);
    CHECK(orr_frame_name("sky", 7, 120, name, sizeof name, &err) == ORR_OK);
    CHECK(strcmp(name, "sky_0007") == 0);
    CHECK(orr_frame_name("sky", 9999, 10000, name, sizeof name, &err) == ORR_OK);
    CHECK(strcmp(name, "sky_9999") == 0);
    CHECK(orr_frame_name("sky", 7, 10001, name, sizeof name, &err) == ORR_OK);
    CHECK(strcmp(name, "sky_00007") == 0);
    char tiny[6];
    CHECK(orr_frame_name("sky", 7, 120, tiny, sizeof tiny, &err) == ORR_ERR_USAGE);
}

static void test_frame_times(void)
{
    orr_frame_time a = orr_frame_at(0, 5, 25, 2.0, 4.0), b = orr_frame_at(4, 5, 25, 2.0, 4.0),
                   c = orr_frame_at(1, 5, 25, 2.0, 4.0), still = orr_frame_at(0, 1, 25, 3.0, 3.0);
    CHECK_NEAR(a.u, 0, 0);
    CHECK_NEAR(b.u, 1, 0);
    CHECK_NEAR(c.u, 0.25, 1e-15);
    CHECK_NEAR(a.time, 2.0, 0);
    CHECK_NEAR(b.time, 4.0, 0);
    CHECK_NEAR(c.time, 2.5, 1e-15);
    CHECK_NEAR(c.seconds, 1.0 / 25, 1e-15);
    CHECK_NEAR(still.u, 0, 0);
}

/* Every frame is taken by exactly one of `jobs` jobs. */
static void test_jobs_share_frames(void)
{
    orr_animation_options o = orr_animation_defaults();
    o.first = 3;
    o.last = 40;
    long total = 0;
    for (int jobs = 1; jobs <= 5; jobs++) {
        total = 0;
        o.stride = jobs;
        for (int k = 0; k < jobs; k++) {
            o.start = k;
            total += orr_animation_count(&o, 100);
        }
        CHECK(total == 38);
    }
    o = orr_animation_defaults();
    CHECK(orr_animation_count(&o, 100) == 100);
    o.last = 500; /* clamped to the run */
    CHECK(orr_animation_count(&o, 10) == 10);
}

typedef struct tally {
    int rendered, skipped;
    long frames[16];
    int n;
} tally;

static void count_frame(void *user, long frame, int skipped)
{
    tally *t = user;
    if (skipped)
        t->skipped++;
    else
        t->rendered++;
    if (t->n < 16)
        t->frames[t->n++] = frame;
}

static orr_status run(const orr_scene *s, int force, tally *t)
{
    memset(t, 0, sizeof *t);
    orr_animation_options o = orr_animation_defaults();
    o.force = force;
    o.done = count_frame;
    o.done_user = t;
    orr_render_report rep;
    orr_error err = {0};
    const orr_scene *list[1] = {s};
    orr_status st = orr_render_animation(list, 1, &o, &rep, &err);
    if (st)
        fprintf(stderr, "render failed: %s\n", err.msg);
    return st;
}

static long fits_key_long(const char *path, const char *key)
{
    fitsfile *f;
    int status = 0;
    long v = -1;
    fits_open_file(&f, path, READONLY, &status);
    fits_read_key(f, TLONG, key, &v, NULL, &status);
    fits_close_file(f, &status);
    return status ? -1 : v;
}

static void test_resume(void)
{
    make_tmpdir();
    static const char yaml[] = "input: {model: {name: mw-m31, particles: 2000}}\n"
                               "camera: {projection: orthographic, width: 300}\n"
                               "image: {width: 32, height: 32}\n"
                               "animation: {frames: 3}\n"
                               "output: {name: clip}\n";
    orr_scene *s = calloc(1, sizeof *s);
    orr_error err = {0};
    CHECK(orr_scene_load_string(s, yaml, "clip.yaml", ".", NULL, 0, &err) == ORR_OK);
    snprintf(s->out_dir, sizeof s->out_dir, "%s", tmpdir);
    tally t;
    CHECK(run(s, 0, &t) == ORR_OK);
    CHECK(t.rendered == 3 && t.skipped == 0);
    CHECK(t.frames[0] == 0 && t.frames[1] == 1 && t.frames[2] == 2);
    char path[512];
    snprintf(path, sizeof path, "%s/clip_0002.fits", tmpdir);
    CHECK(fits_key_long(path, "FRAME") == 2);
    CHECK(fits_key_long(path, "NFRAMES") == 3);
    snprintf(path, sizeof path, "%s/clip_0001.png", tmpdir);
    CHECK(access(path, F_OK) == 0);

    /* Everything complete: nothing rendered again. */
    CHECK(run(s, 0, &t) == ORR_OK);
    CHECK(t.rendered == 0 && t.skipped == 3);

    /* A truncated output (as from a copy cut short) is redone, alone. */
    CHECK(truncate(path, 10) == 0);
    CHECK(run(s, 0, &t) == ORR_OK);
    CHECK(t.rendered == 1 && t.skipped == 2);
    struct stat st;
    CHECK(stat(path, &st) == 0 && st.st_size > 10);

    /* A missing output too. */
    snprintf(path, sizeof path, "%s/clip_0000.fits", tmpdir);
    CHECK(unlink(path) == 0);
    CHECK(run(s, 0, &t) == ORR_OK);
    CHECK(t.rendered == 1 && t.skipped == 2 && t.frames[0] == 0);

    /* --force redoes every frame. */
    CHECK(run(s, 1, &t) == ORR_OK);
    CHECK(t.rendered == 3 && t.skipped == 0);

    /* A still keeps its plain name and leaves no marker. */
    s->anim_frames = 1;
    snprintf(s->out_name, sizeof s->out_name, "still");
    CHECK(run(s, 0, &t) == ORR_OK);
    snprintf(path, sizeof path, "%s/still.png", tmpdir);
    CHECK(access(path, F_OK) == 0);
    snprintf(path, sizeof path, "%s/.orrery-frames/still.done", tmpdir);
    CHECK(access(path, F_OK) != 0);
    free(s);
    remove_tmpdir();
}

int main(void)
{
    test_frame_names();
    test_frame_times();
    test_jobs_share_frames();
    test_resume();
    return check_summary();
}
