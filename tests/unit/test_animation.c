/* Runs of frames: frame names, frame times, the frames a job takes, and
 * resumption (complete frames skipped, a truncated one redone). */
#include <fitsio.h>
#include <stdlib.h>
#include <sys/stat.h>
#include <unistd.h>

#include "check.h"
#include "core/owned.h"
#include "render/animation.h"
#include "scene/scene.h"
#include "tmpdir.h"

/* Checks that frame `frame` of a run of nframes named as f says is want. */
static void check_name(const orr_frame_naming *f, long frame, long nframes, const char *want)
{
    char name[64];
    orr_error err = {0};
    CHECK(orr_frame_name(f, "sky", frame, nframes, name, sizeof name, &err) == ORR_OK);
    CHECK(strcmp(name, want) == 0);
    if (strcmp(name, want) != 0)
        fprintf(stderr, "  frame %ld of %ld: got %s, expected %s\n", frame, nframes, name, want);
}

static void test_frame_names(void)
{
    const orr_frame_naming def = ORR_FRAME_NAMING_DEFAULT;
    check_name(&def, 0, 1, "sky");
    check_name(&def, 7, 120, "sky_0007");
    check_name(&def, 9999, 10000, "sky_9999");
    check_name(&def, 7, 10001, "sky_00007");
    char tiny[6];
    orr_error err = {0};
    CHECK(orr_frame_name(&def, "sky", 7, 120, tiny, sizeof tiny, &err) == ORR_ERR_USAGE);

    /* The fulldome delivery convention: from 1, five digits, a dot. */
    const orr_frame_naming dome = {.start = 1, .digits = 5, .separator = "."};
    check_name(&dome, 0, 120, "sky.00001");
    check_name(&dome, 99998, 99999, "sky.99999");
    /* The last number needs a sixth digit: every frame gets it. */
    check_name(&dome, 0, 100000, "sky.000001");
    const orr_frame_naming late = {.start = 9990, .digits = 4, .separator = "-"};
    CHECK(orr_frame_digits(&late, 10) == 4 && orr_frame_digits(&late, 11) == 5);
    check_name(&late, 0, 11, "sky-09990");
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
    int rendered, skipped, redone;
    long frames[16];
    int n;
    char why[512]; /* the first reason a frame was redone */
} tally;

static void count_frame(void *user, long frame, int skipped, const char *redone)
{
    tally *t = user;
    if (redone && t->redone++ == 0)
        snprintf(t->why, sizeof t->why, "%s", redone);
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
    orr_owned_set(&s->output.dir, tmpdir, NULL);
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
    s->animation.frames = 1;
    snprintf(s->output.name, sizeof s->output.name, "still");
    CHECK(run(s, 0, &t) == ORR_OK);
    snprintf(path, sizeof path, "%s/still.png", tmpdir);
    CHECK(access(path, F_OK) == 0);
    snprintf(path, sizeof path, "%s/.orrery-frames/still.done", tmpdir);
    CHECK(access(path, F_OK) != 0);
    orr_scene_free(s);
    free(s);
    remove_tmpdir();
}

/* Loads the clip scene of the tests below with overrides, into tmpdir. */
static orr_scene *load_clip(const char *yaml, const char *const *sets, int nsets)
{
    orr_scene *s = calloc(1, sizeof *s);
    orr_error err = {0};
    if (orr_scene_load_string(s, yaml, "clip.yaml", tmpdir, sets, nsets, &err) != ORR_OK) {
        fprintf(stderr, "scene: %s\n", err.msg);
        exit(1);
    }
    orr_owned_set(&s->output.dir, tmpdir, NULL);
    return s;
}

/* A frame made with other settings is redone, and the reason names the
 * key; so is one whose input file changed, or whose output changed without
 * changing size. */
static void test_resume_checks_what_made_the_frame(void)
{
    make_tmpdir();
    char table[600];
    snprintf(table, sizeof table, "%s/stars.txt", tmpdir);
    FILE *f = fopen(table, "w");
    fputs("x y z mass\n0 0 0 1\n1 2 0 1\n-3 1 0 2\n", f);
    fclose(f);
    static const char yaml[] = "input: {file: stars.txt}\n"
                               "camera: {projection: orthographic, width: 10}\n"
                               "image: {width: 24, height: 24}\n"
                               "animation: {frames: 4}\n"
                               "output: {name: clip, fits: false}\n";
    /* Frames 0-1 of a run at one size, as `--frames 0:1` would... */
    const char *small[] = {"image.width=16"};
    orr_scene *s = load_clip(yaml, small, 1);
    orr_animation_options o = orr_animation_defaults();
    tally t = {0};
    o.last = 1;
    o.done = count_frame;
    o.done_user = &t;
    orr_render_report rep;
    orr_error err = {0};
    const orr_scene *list[1] = {s};
    CHECK(orr_render_animation(list, 1, &o, &rep, &err) == ORR_OK);
    CHECK(t.rendered == 2);
    orr_scene_free(s);
    free(s);

    /* ...then the whole run at another: every frame is this run's. */
    s = load_clip(yaml, NULL, 0);
    CHECK(run(s, 0, &t) == ORR_OK);
    CHECK(t.rendered == 4 && t.skipped == 0 && t.redone == 2);
    CHECK(strstr(t.why, "image.width changed from 16 to 24") != NULL);
    CHECK(run(s, 0, &t) == ORR_OK);
    CHECK(t.skipped == 4 && t.redone == 0);

    /* A longer run of the same path moves every frame's camera. */
    const char *longer[] = {"animation.frames=5"};
    orr_scene *s5 = load_clip(yaml, longer, 1);
    CHECK(run(s5, 0, &t) == ORR_OK);
    CHECK(t.rendered == 5 && t.redone == 4);
    CHECK(strstr(t.why, "animation.frames changed from 4 to 5") != NULL);
    orr_scene_free(s5);
    free(s5);

    /* An output changed in place, same size: caught by its checksum. */
    char png[700];
    snprintf(png, sizeof png, "%s/clip_0002.png", tmpdir);
    CHECK(run(s, 0, &t) == ORR_OK); /* back to 4 frames */
    FILE *g = fopen(png, "r+b");
    CHECK(g != NULL);
    if (g) {
        fseek(g, 100, SEEK_SET);
        int c = fgetc(g);
        fseek(g, 100, SEEK_SET);
        fputc(c ^ 0x5a, g);
        fclose(g);
    }
    CHECK(run(s, 0, &t) == ORR_OK);
    CHECK(t.rendered == 1 && t.skipped == 3 && strstr(t.why, "checksum") != NULL);

    /* The input file rewritten: every frame again. */
    f = fopen(table, "a");
    fputs("2 2 0 1\n", f);
    fclose(f);
    CHECK(run(s, 0, &t) == ORR_OK);
    CHECK(t.rendered == 4 && strstr(t.why, "input.file") != NULL);
    CHECK(run(s, 0, &t) == ORR_OK);
    CHECK(t.skipped == 4);

    /* A marker from an older orrery is not trusted. */
    char marker[700];
    snprintf(marker, sizeof marker, "%s/.orrery-frames/clip_0000.done", tmpdir);
    f = fopen(marker, "w");
    fputs("orrery-frame 1\n100 clip_0000.png\n", f);
    fclose(f);
    CHECK(run(s, 0, &t) == ORR_OK);
    CHECK(t.rendered == 1 && strstr(t.why, "older") != NULL);
    orr_scene_free(s);
    free(s);
    remove_tmpdir();
}

/* A frame that fails part-way leaves none of its new outputs and no
 * marker: the earlier frame's files are untouched, and the next run
 * redoes it. */
static void test_failed_frame_writes_nothing(void)
{
    make_tmpdir();
    static const char yaml[] = "input: {model: {name: mw-m31, particles: 1000}}\n"
                               "camera: {projection: orthographic, width: 300}\n"
                               "image: {width: 16, height: 16}\n"
                               "output: {name: s, raw: true, exr: true}\n";
    orr_scene *s = load_clip(yaml, NULL, 0);
    char dir[700], path[700];
    snprintf(dir, sizeof dir, "%s/s.png", tmpdir); /* a folder where the PNG would go */
    CHECK(mkdir(dir, 0777) == 0);
    tally t;
    CHECK(run(s, 0, &t) != ORR_OK);
    const char *names[] = {"s.fits", "s.raw.fits", "s.exr"};
    for (int i = 0; i < 3; i++) {
        snprintf(path, sizeof path, "%s/%s", tmpdir, names[i]);
        CHECK(access(path, F_OK) != 0);
    }
    CHECK(count_entries() == 1); /* the folder alone: no temporary file either */
    orr_scene_free(s);
    free(s);
    remove_tmpdir();
}

int main(void)
{
    test_frame_names();
    test_frame_times();
    test_jobs_share_frames();
    test_resume();
    test_resume_checks_what_made_the_frame();
    test_failed_frame_writes_nothing();
    return check_summary();
}
