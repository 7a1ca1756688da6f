/* Where a frame's time goes (core/timings.h, orrery render --timings):
 * every stage a frame runs is reported, none is negative, and the stages
 * add up to the frame's own wall and CPU time. */
#include <stdlib.h>

#include "check.h"
#include "core/owned.h"
#include "render/animation.h"
#include "render/render.h"
#include "scene/scene.h"
#include "tmpdir.h"

#define MODEL "input: {model: {name: mw-m31, particles: 60000, seed: 4}, chunk: 20000}\n"

static orr_status render_yaml(const char *yaml, const char *name, orr_render_report *rep, orr_error *err)
{
    orr_scene *s = calloc(1, sizeof *s);
    CHECK(s != NULL);
    orr_status st = orr_scene_load_string(s, yaml, name, ".", NULL, 0, err);
    if (!st) {
        orr_owned_set(&s->output.dir, tmpdir, NULL);
        snprintf(s->output.name, sizeof s->output.name, "%s", name);
        st = orr_render_scene(s, rep, NULL, NULL, err);
    }
    orr_scene_free(s);
    free(s);
    return st;
}

/* Every stage at least 0; the stages summed within 5 % (and 20 ms, for
 * what belongs to none: the frame's last frees) of the frame's totals,
 * which are measured on their own. */
static void check_adds_up(const orr_stage_times *t)
{
    for (int s = 0; s < ORR_NSTAGES; s++) {
        CHECK(t->wall[s] >= 0.0);
        CHECK(t->cpu[s] >= 0.0);
    }
    double wall, cpu;
    orr_stage_times_sum(t, &wall, &cpu);
    CHECK(t->total_wall > 0.0);
    CHECK(wall <= t->total_wall + 1e-9);
    CHECK_NEAR(wall, t->total_wall, 0.05 * t->total_wall + 0.02);
    CHECK_NEAR(cpu, t->total_cpu, 0.05 * t->total_cpu + 0.02);
}

/* A colour dome master with the PSF core drawn on every star, FITS and PNG:
 * the stages it runs take time, those it does not take none. */
static void test_dome_frame(void)
{
    orr_render_report rep;
    orr_error err = {0};
    orr_status st = render_yaml(MODEL "camera: {projection: dome, position: [8, 0, 0]}\n"
                                      "image: {width: 400, height: 400}\ndeposit: cic\n"
                                      "psf: {kind: gaussian}\n"
                                      "colour:\n  populations:\n"
                                      "    - {name: all, colour: {temperature: 5000}, luminance: {mass: 1}}\n",
                                "dome", &rep, &err);
    CHECK(st == ORR_OK);
    if (st)
        fprintf(stderr, "%s\n", err.msg);
    const orr_stage_times *t = &rep.times;
    CHECK(t->frames == 1);
    check_adds_up(t);
    const orr_stage ran[] = {ORR_STAGE_SETUP, ORR_STAGE_SOURCE, ORR_STAGE_GATHER, ORR_STAGE_DEPOSIT,
                             ORR_STAGE_REDUCE, ORR_STAGE_POST, ORR_STAGE_FITS, ORR_STAGE_PNG, ORR_STAGE_COMMIT};
    for (size_t k = 0; k < sizeof ran / sizeof ran[0]; k++)
        if (!(t->wall[ran[k]] > 0.0)) {
            fprintf(stderr, "stage %s took no time\n", orr_stage_name(ran[k]));
            CHECK(!"a stage the frame ran took no time");
        }
    CHECK(t->wall[ORR_STAGE_EXR] == 0.0 && t->wall[ORR_STAGE_IMAGE] == 0.0 && t->wall[ORR_STAGE_STEREO] == 0.0);
    /* No lengths to compute: CPU time, not wall, since a loaded machine may
     * deschedule the thread inside the stage for longer than its work
     * (it did: 10 ms of wall under a CI run beside an N-body run). */
    CHECK(t->cpu[ORR_STAGE_LENGTHS] < 0.01);
    /* 60000 CIC kernels 3.2 pixels wide cost more than their projection. */
    CHECK(t->wall[ORR_STAGE_DEPOSIT] > t->wall[ORR_STAGE_GATHER]);
}

/* A flat view's PSF is its convolution: its own stage. */
static void test_flat_psf(void)
{
    orr_render_report rep;
    orr_error err = {0};
    orr_status st = render_yaml(MODEL "camera: {projection: orthographic, width: 60}\n"
                                      "image: {width: 300, height: 200}\ndeposit: ngp\n"
                                      "psf: {kind: gaussian, fwhm: 3}\n",
                                "flat", &rep, &err);
    CHECK(st == ORR_OK);
    check_adds_up(&rep.times);
    CHECK(rep.times.wall[ORR_STAGE_PSF] > 0.0);
}

typedef struct seen {
    int calls;
    long frames[8];
    orr_stage_times sum;
} seen;

static void timed(void *user, long frame, const orr_stage_times *t)
{
    seen *s = user;
    if (s->calls < 8)
        s->frames[s->calls] = frame;
    s->calls++;
    check_adds_up(t);
    orr_stage_times_add(&s->sum, t);
}

/* A run tells the caller each rendered frame's times, and they add up to
 * a run's total; frames skipped as complete are not told. */
static void test_run(void)
{
    orr_scene *s = calloc(1, sizeof *s);
    orr_error err = {0};
    CHECK(orr_scene_load_string(s, MODEL "camera: {projection: orthographic, width: 60}\n"
                                         "image: {width: 64, height: 48}\ndeposit: ngp\nanimation: {frames: 3}\n",
                                "run", ".", NULL, 0, &err) == ORR_OK);
    orr_owned_set(&s->output.dir, tmpdir, NULL);
    snprintf(s->output.name, sizeof s->output.name, "run");
    const orr_scene *list[1] = {s};
    orr_render_report rep;
    orr_animation_options opt = orr_animation_defaults();
    seen got;
    memset(&got, 0, sizeof got);
    opt.timed = timed;
    opt.timed_user = &got;
    CHECK(orr_render_animation(list, 1, &opt, &rep, &err) == ORR_OK);
    CHECK(got.calls == 3);
    CHECK(got.frames[0] == 0 && got.frames[1] == 1 && got.frames[2] == 2);
    CHECK(got.sum.frames == 3);
    double wall, cpu;
    orr_stage_times_sum(&got.sum, &wall, &cpu);
    CHECK_NEAR(wall, got.sum.total_wall, 0.05 * got.sum.total_wall + 0.06);
    /* Again: every frame complete, skipped, not timed. */
    memset(&got, 0, sizeof got);
    CHECK(orr_render_animation(list, 1, &opt, &rep, &err) == ORR_OK);
    CHECK(got.calls == 0);
    orr_scene_free(s);
    free(s);
}

/* Threaded work is shared between two stages by the workers' clocks; with
 * no work measured (0 / 0) all of it goes to the first, none is lost. */
static void test_split(void)
{
    orr_stage_times t;
    memset(&t, 0, sizeof t);
    orr_clock at = orr_clock_now();
    at.wall -= 1.0;
    at.cpu -= 0.5;
    orr_stage_charge_split(&t, ORR_STAGE_GATHER, ORR_STAGE_DEPOSIT, 0.25, &at);
    CHECK_NEAR(t.wall[ORR_STAGE_GATHER] / (t.wall[ORR_STAGE_GATHER] + t.wall[ORR_STAGE_DEPOSIT]), 0.25, 1e-12);
    CHECK(t.wall[ORR_STAGE_GATHER] + t.wall[ORR_STAGE_DEPOSIT] >= 1.0);
    CHECK(t.cpu[ORR_STAGE_GATHER] + t.cpu[ORR_STAGE_DEPOSIT] >= 0.5);
    memset(&t, 0, sizeof t);
    at.wall -= 1.0;
    orr_stage_charge_split(&t, ORR_STAGE_GATHER, ORR_STAGE_DEPOSIT, 0.0 / 0.0, &at);
    CHECK(t.wall[ORR_STAGE_GATHER] >= 1.0 && t.wall[ORR_STAGE_DEPOSIT] == 0.0);
    CHECK(strcmp(orr_stage_name(ORR_STAGE_DEPOSIT), "deposit") == 0);
    CHECK(strcmp(orr_stage_name(ORR_NSTAGES), "?") == 0);
}

/* A thread's work beside other stages (the FITS file beside the PNG): the
 * thread's CPU goes to its stage, taken from the others in proportion to
 * theirs, walls with it, and the sums do not change. */
static void test_beside(void)
{
    orr_stage_times before = {0}, t = {0};
    t.cpu[ORR_STAGE_POST] = 1.0, t.wall[ORR_STAGE_POST] = 1.0;
    t.cpu[ORR_STAGE_PNG] = 3.0, t.wall[ORR_STAGE_PNG] = 2.0;
    t.cpu[ORR_STAGE_FITS] = 0.5, t.wall[ORR_STAGE_FITS] = 0.5; /* the wait for the thread */
    orr_stage_charge_beside(&t, &before, ORR_STAGE_FITS, 2.5); /* 2 of its 2.5 s were charged to the others */
    CHECK_NEAR(t.cpu[ORR_STAGE_FITS], 2.5, 1e-12);
    CHECK_NEAR(t.cpu[ORR_STAGE_POST], 0.5, 1e-12);
    CHECK_NEAR(t.cpu[ORR_STAGE_PNG], 1.5, 1e-12);
    CHECK_NEAR(t.wall[ORR_STAGE_POST], 0.5, 1e-12);
    CHECK_NEAR(t.wall[ORR_STAGE_PNG], 1.0, 1e-12);
    CHECK_NEAR(t.wall[ORR_STAGE_FITS], 2.0, 1e-12);
    double wall, cpu;
    orr_stage_times_sum(&t, &wall, &cpu);
    CHECK_NEAR(wall, 3.5, 1e-12);
    CHECK_NEAR(cpu, 4.5, 1e-12);
    /* More thread CPU than the clock gave the others: they give all they had. */
    orr_stage_times u = before;
    u.cpu[ORR_STAGE_PNG] = 1.0, u.wall[ORR_STAGE_PNG] = 1.0;
    orr_stage_charge_beside(&u, &before, ORR_STAGE_FITS, 5.0);
    CHECK(u.cpu[ORR_STAGE_PNG] == 0.0 && u.cpu[ORR_STAGE_FITS] == 1.0 && u.wall[ORR_STAGE_FITS] == 1.0);
}

int main(void)
{
    RUN(test_beside);
    make_tmpdir();
    RUN(test_dome_frame);
    RUN(test_flat_psf);
    RUN(test_run);
    RUN(test_split);
    remove_tmpdir();
    return check_summary();
}
