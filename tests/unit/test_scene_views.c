/* Scene views (several renders from one scene file) and dome profiles (the
 * files camera.dome names): where profiles are found, what they supply,
 * what wins over them, and the messages of bad ones. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "check.h"
#include "scene/scene.h"

/* An orr_scene_views is ~140 KB: one heap copy for every test. */
static orr_scene_views *g_views;
static orr_scene g_scene;

/* A scratch folder for profile and scene files, removed at the end. */
static char g_tmp[64];

#define MODEL "input:\n  model:\n    name: mw-m31\n"

/* ---- files ---- */

static int write_text(const char *path, const char *text)
{
    FILE *f = fopen(path, "w");
    if (!f)
        return 0;
    int ok = fputs(text, f) >= 0;
    return fclose(f) == 0 && ok;
}

/* g_tmp/rel, in buf. */
static const char *tmp_path(char *buf, size_t size, const char *rel)
{
    snprintf(buf, size, "%s/%s", g_tmp, rel);
    return buf;
}

static void make_dir(const char *rel)
{
    char path[256];
    CHECK(mkdir(tmp_path(path, sizeof path, rel), 0755) == 0);
}

static void write_tmp(const char *rel, const char *text)
{
    char path[256];
    CHECK(write_text(tmp_path(path, sizeof path, rel), text));
}

static void remove_tmp(const char *rel)
{
    char path[256];
    CHECK(remove(tmp_path(path, sizeof path, rel)) == 0);
}

/* The repository's domes/ folder, found from this file's path. */
static void repo_domes(char *buf, size_t size)
{
    char here[512];
    snprintf(here, sizeof here, "%s", __FILE__);
    char *slash = strrchr(here, '/');
    if (slash)
        *slash = '\0';
    else
        snprintf(here, sizeof here, ".");
    snprintf(buf, size, "%s/../../domes", here);
}

static void set_domes(const char *value)
{
    if (value)
        CHECK(setenv("ORRERY_DOMES", value, 1) == 0);
    else
        CHECK(unsetenv("ORRERY_DOMES") == 0);
}

/* ---- loading ---- */

static orr_status load_views(const char *yaml, const char *const *sets, int nsets, orr_error *err)
{
    orr_error_clear(err);
    orr_scene_views_free(g_views);
    return orr_scene_load_views_string(g_views, yaml, "sky.yaml", "/nonexistent/scenes", sets, nsets, err);
}

static orr_status load_one(const char *yaml, const char *const *sets, int nsets, orr_error *err)
{
    orr_error_clear(err);
    orr_scene_free(&g_scene);
    return orr_scene_load_string(&g_scene, yaml, "sky.yaml", "/nonexistent/scenes", sets, nsets, err);
}

#define EXPECT_VIEWS_OK(yaml, sets, nsets)                              \
    do {                                                                \
        orr_error e_;                                                   \
        orr_status st_ = load_views((yaml), (sets), (nsets), &e_);      \
        CHECK(st_ == ORR_OK);                                           \
        if (st_ != ORR_OK)                                              \
            fprintf(stderr, "  unexpected error: %s\n", e_.msg);        \
    } while (0)

/* Loads the views and checks for a usage error containing each fragment. */
#define EXPECT_VIEWS_ERROR(yaml, sets, nsets, ...)                                   \
    do {                                                                             \
        orr_error e_;                                                                \
        orr_status st_ = load_views((yaml), (sets), (nsets), &e_);                   \
        CHECK(st_ == ORR_ERR_USAGE);                                                 \
        if (st_ != ORR_ERR_USAGE)                                                    \
            fprintf(stderr, "  got status %d: %s\n", (int)st_, e_.msg);              \
        const char *needles_[] = {__VA_ARGS__};                                      \
        for (size_t i_ = 0; i_ < sizeof needles_ / sizeof needles_[0]; i_++)         \
            CHECK_CONTAINS(e_.msg, needles_[i_]);                                    \
    } while (0)

/* ---- dome profiles ---- */

static void test_repo_profiles(void)
{
    static const struct {
        const char *name;
        double fov, tilt;
        int size;
    } want[] = {
        {"flat-180", 180, 0, 3600},    {"tilted-30", 180, 30, 3600},   {"fisheye-210", 210, 0, 4096},
        {"fisheye-230", 230, 0, 4096}, {"flat-180-4k", 180, 0, 4096}, {"flat-180-8k", 180, 0, 8192},
    };
    char domes[600];
    repo_domes(domes, sizeof domes);
    set_domes(domes);
    for (size_t i = 0; i < sizeof want / sizeof want[0]; i++) {
        char set[64];
        snprintf(set, sizeof set, "camera.dome=%s", want[i].name);
        const char *sets[] = {set};
        orr_error err;
        orr_status st = load_one(MODEL "camera: {projection: dome}\n", sets, 1, &err);
        CHECK(st == ORR_OK);
        if (st != ORR_OK)
            fprintf(stderr, "  %s: %s\n", want[i].name, err.msg);
        CHECK(g_scene.projection.dome_fov_deg == want[i].fov);
        CHECK(g_scene.camera.dome_tilt == want[i].tilt);
        CHECK(g_scene.projection.width == want[i].size && g_scene.projection.height == want[i].size);
        CHECK(strcmp(g_scene.camera.dome, want[i].name) == 0);
    }
    set_domes(NULL);
}

static void test_profile_search(void)
{
    /* g_tmp/env1 (empty), g_tmp/env2/p.yaml, g_tmp/domes/p.yaml and
     * q.yaml, g_tmp/scenes/domes/r.yaml, the scene in g_tmp/scenes. */
    make_dir("env1");
    make_dir("env2");
    make_dir("domes");
    make_dir("scenes");
    make_dir("scenes/domes");
    write_tmp("env2/p.yaml", "description: from ORRERY_DOMES\nfov: 200\ntilt: 10\nsize: 64\n");
    write_tmp("domes/p.yaml", "fov: 220\n");
    write_tmp("domes/q.yaml", "description: from ../domes\nsize: 32\n");
    write_tmp("scenes/domes/r.yaml", "tilt: 45\n");
    write_tmp("scenes/sky.yaml", MODEL "camera:\n  projection: dome\n  dome: p\n");
    char scene[256], env[512], e1[128], e2[128];
    tmp_path(scene, sizeof scene, "scenes/sky.yaml");
    orr_error err;

    /* The first folder of ORRERY_DOMES that has it wins over ../domes;
     * empty entries are skipped. */
    snprintf(env, sizeof env, ":%s::%s:", tmp_path(e1, sizeof e1, "env1"), tmp_path(e2, sizeof e2, "env2"));
    set_domes(env);
    orr_scene_free(&g_scene);
    CHECK(orr_scene_load(&g_scene, scene, NULL, 0, &err) == ORR_OK);
    CHECK(g_scene.projection.dome_fov_deg == 200 && g_scene.camera.dome_tilt == 10);
    CHECK(g_scene.projection.width == 64 && g_scene.projection.height == 64);

    /* Without it, <scene folder>/../domes; keys the profile leaves out keep their defaults. */
    set_domes(NULL);
    orr_scene_free(&g_scene);
    CHECK(orr_scene_load(&g_scene, scene, NULL, 0, &err) == ORR_OK);
    CHECK(g_scene.projection.dome_fov_deg == 220 && g_scene.camera.dome_tilt == 0);
    CHECK(g_scene.projection.width == 1024);
    const char *q[] = {"camera.dome=q"};
    orr_scene_free(&g_scene);
    CHECK(orr_scene_load(&g_scene, scene, q, 1, &err) == ORR_OK);
    CHECK(g_scene.projection.width == 32 && g_scene.projection.dome_fov_deg == 180);

    /* Then <scene folder>/domes. */
    const char *r[] = {"camera.dome=r"};
    orr_scene_free(&g_scene);
    CHECK(orr_scene_load(&g_scene, scene, r, 1, &err) == ORR_OK);
    CHECK(g_scene.camera.dome_tilt == 45);

    /* A name found nowhere lists every folder searched. */
    set_domes(e1);
    const char *none[] = {"camera.dome=nope"};
    orr_scene_free(&g_scene);
    CHECK(orr_scene_load(&g_scene, scene, none, 1, &err) == ORR_ERR_USAGE);
    char want[600];
    snprintf(want, sizeof want, "--set camera.dome=nope: camera.dome: no dome profile 'nope': looked for nope.yaml in %s, "
             "%s/scenes/../domes, %s/scenes/domes", e1, g_tmp, g_tmp);
    CHECK_CONTAINS(err.msg, want);
    CHECK_CONTAINS(err.msg, "ORRERY_DOMES");
    set_domes(NULL);

    remove_tmp("scenes/sky.yaml");
    remove_tmp("scenes/domes/r.yaml");
    remove_tmp("domes/q.yaml");
    remove_tmp("domes/p.yaml");
    remove_tmp("env2/p.yaml");
    remove_tmp("scenes/domes");
    remove_tmp("scenes");
    remove_tmp("domes");
    remove_tmp("env2");
    remove_tmp("env1");
}

/* Writes g_tmp/bad.yaml, loads a dome scene naming it and checks the message. */
static void expect_bad_profile(const char *profile, const char *fragment)
{
    write_tmp("bad.yaml", profile);
    set_domes(g_tmp);
    orr_error err;
    CHECK(load_one(MODEL "camera:\n  projection: dome\n  dome: bad\n", NULL, 0, &err) == ORR_ERR_USAGE);
    char want[512];
    snprintf(want, sizeof want, "%s/bad.yaml%s", g_tmp, fragment);
    CHECK_CONTAINS(err.msg, want);
    set_domes(NULL);
    remove_tmp("bad.yaml");
}

static void test_bad_profiles(void)
{
    expect_bad_profile("description: x\nfov: 400\n", ":2: fov: 400 is out of range (90 to 360)");
    expect_bad_profile("fvo: 180\n", ":1: unknown key 'fvo' (did you mean 'fov'?)");
    expect_bad_profile("colour: red\n", ":1: unknown key 'colour' (see domes/README.md for the keys)");
    expect_bad_profile("tilt: 95\n", ":1: tilt: 95 is out of range (0 to 90)");
    expect_bad_profile("size: 0\n", ":1: size: 0 is out of range (1 to 65536)");
    expect_bad_profile("size: 4096\nsize: 2048\n", ":2: duplicate key 'size' (first set at line 1)");
    expect_bad_profile("description: [a]\n", ":1: description: expected a string, got a list");
    expect_bad_profile("fov: [180\n", ":2:1: YAML syntax error");
    expect_bad_profile("# nothing\n", ": the dome profile is empty");
    expect_bad_profile("- fov\n", ":1: a dome profile must be a mapping of keys, not a list");
    /* A bad profile is an error whatever the projection. */
    write_tmp("bad.yaml", "fov: 10\n");
    set_domes(g_tmp);
    orr_error err;
    CHECK(load_one(MODEL "camera:\n  projection: hammer-aitoff\n  dome: bad\n", NULL, 0, &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "bad.yaml:1: fov: 10 is out of range");
    set_domes(NULL);
    remove_tmp("bad.yaml");
}

static void test_profile_precedence(void)
{
    write_tmp("big.yaml", "fov: 200\ntilt: 20\nsize: 2048\n");
    set_domes(g_tmp);
    orr_error err;
    const char *dome = MODEL "camera:\n  projection: dome\n  dome: big\n";
    /* The scene's own values win over the profile's, key by key. */
    CHECK(load_one(MODEL "camera:\n  projection: dome\n  dome: big\n  dome_fov: 190\nimage:\n  width: 1000\n", NULL,
                   0, &err) == ORR_OK);
    CHECK(g_scene.projection.dome_fov_deg == 190 && g_scene.camera.dome_tilt == 20);
    CHECK(g_scene.projection.width == 1000 && g_scene.projection.height == 2048);
    /* So do --set values, even ones equal to the defaults. */
    const char *sets[] = {"image.height=500", "camera.dome_tilt=0", "camera.dome_fov=180"};
    CHECK(load_one(dome, sets, 3, &err) == ORR_OK);
    CHECK(g_scene.projection.height == 500 && g_scene.projection.width == 2048);
    CHECK(g_scene.camera.dome_tilt == 0 && g_scene.projection.dome_fov_deg == 180);
    /* The profile applies to dome masters only. */
    const char *pano[] = {"camera.projection=hammer-aitoff"};
    CHECK(load_one(dome, pano, 1, &err) == ORR_OK);
    CHECK(g_scene.projection.width == 1024 && g_scene.projection.dome_fov_deg == 180 && g_scene.camera.dome_tilt == 0);
    set_domes(NULL);
    remove_tmp("big.yaml");
}

/* ---- views ---- */

/* The Future Sky shape: an observer, a dome master and a panorama. */
#define SKY                                          \
    MODEL                                            \
    "observer: {id: 1, reference_id: 2}\n"           \
    "camera:\n"                                      \
    "  dome: flat-180\n"                             \
    "output:\n"                                      \
    "  colormap: inferno\n"                          \
    "views:\n"                                       \
    "  dome:\n"                                      \
    "    camera: {projection: dome}\n"               \
    "  panorama:\n"                                  \
    "    camera:\n"                                  \
    "      projection: hammer-aitoff\n"              \
    "      lon_flip: true\n"                         \
    "    image: {width: 4096, height: 2048}\n"

static void use_repo_domes(void)
{
    char domes[600];
    repo_domes(domes, sizeof domes);
    set_domes(domes);
}

static void test_two_views(void)
{
    use_repo_domes();
    EXPECT_VIEWS_OK(SKY, NULL, 0);
    CHECK(g_views->n == 2);
    CHECK(strcmp(g_views->name[0], "dome") == 0 && strcmp(g_views->name[1], "panorama") == 0);
    const orr_scene *dome = &g_views->view[0], *pano = &g_views->view[1];
    CHECK(dome->projection.kind == ORR_PROJ_DOME);
    CHECK(dome->projection.width == 3600 && dome->projection.height == 3600);
    CHECK(dome->projection.dome_fov_deg == 180 && !dome->projection.lon_flip);
    CHECK(pano->projection.kind == ORR_PROJ_HAMMER_AITOFF && pano->projection.lon_flip);
    CHECK(pano->projection.width == 4096 && pano->projection.height == 2048);
    /* Both share the base scene. */
    for (int i = 0; i < 2; i++) {
        const orr_scene *s = &g_views->view[i];
        CHECK(s->observer.has_id && s->observer.id == 1 && s->observer.reference_id == 2);
        CHECK(s->picture.colormap == ORR_CMAP_INFERNO);
        CHECK(strcmp(s->camera.dome, "flat-180") == 0);
        CHECK(strcmp(s->path, "sky.yaml") == 0 && strcmp(s->dir, "/nonexistent/scenes") == 0);
    }
    /* Default output names: STEM-VIEW. */
    CHECK(strcmp(dome->output.name, "sky-dome") == 0);
    CHECK(strcmp(pano->output.name, "sky-panorama") == 0);
    set_domes(NULL);
}

static void test_view_output_names(void)
{
    /* The base scene's name gets -VIEW with several views... */
    EXPECT_VIEWS_OK(MODEL "output: {name: future}\nviews:\n  a:\n    deposit: ngp\n  b:\n", NULL, 0);
    CHECK(g_views->n == 2);
    CHECK(strcmp(g_views->view[0].output.name, "future-a") == 0);
    CHECK(strcmp(g_views->view[1].output.name, "future-b") == 0);
    CHECK(g_views->view[0].deposit.kind == ORR_DEPOSIT_NGP && g_views->view[1].deposit.kind == ORR_DEPOSIT_CIC);
    /* ...a view's own is kept as it is... */
    EXPECT_VIEWS_OK(MODEL "output: {name: future}\nviews:\n  a: {output: {name: master}}\n  b: {}\n", NULL, 0);
    CHECK(strcmp(g_views->view[0].output.name, "master") == 0);
    CHECK(strcmp(g_views->view[1].output.name, "future-b") == 0);
    /* ...and so is the base's with one view; without a name, STEM-VIEW. */
    EXPECT_VIEWS_OK(MODEL "output: {name: future}\nviews:\n  only: {deposit: ngp}\n", NULL, 0);
    CHECK(g_views->n == 1 && strcmp(g_views->view[0].output.name, "future") == 0);
    EXPECT_VIEWS_OK(MODEL "views:\n  only: {deposit: ngp}\n", NULL, 0);
    CHECK(strcmp(g_views->view[0].output.name, "sky-only") == 0);
    /* Two views writing the same files. */
    EXPECT_VIEWS_ERROR(MODEL "views:\n  a: {output: {name: same}}\n  b: {output: {name: same}}\n", NULL, 0,
                       "sky.yaml: views 'a' and 'b' both write output.name 'same'");
    EXPECT_VIEWS_ERROR(MODEL "views:\n  a-b: {}\n  b: {output: {name: sky-a-b}}\n", NULL, 0,
                       "views 'a-b' and 'b' both write output.name 'sky-a-b'");
}

static void test_view_overrides(void)
{
    use_repo_domes();
    /* Into one view. */
    const char *one[] = {"views.dome.image.width=1800", "views.dome.image.height=1800"};
    EXPECT_VIEWS_OK(SKY, one, 2);
    CHECK(g_views->view[0].projection.width == 1800 && g_views->view[0].projection.height == 1800);
    CHECK(g_views->view[1].projection.width == 4096);
    /* Into the base: every view gets it, unless the view sets the key itself. */
    const char *base[] = {"output.colormap=grey", "image.width=512", "deposit=ngp"};
    EXPECT_VIEWS_OK(SKY, base, 3);
    for (int i = 0; i < 2; i++)
        CHECK(g_views->view[i].picture.colormap == ORR_CMAP_GREY && g_views->view[i].deposit.kind == ORR_DEPOSIT_NGP);
    CHECK(g_views->view[0].projection.width == 512);  /* beats the profile, as a scene value does */
    CHECK(g_views->view[0].projection.height == 3600);
    CHECK(g_views->view[1].projection.width == 4096); /* the view's own value */
    /* A view name that does not exist is a typo, not a new view... */
    const char *typo[] = {"views.doem.image.width=1800"};
    EXPECT_VIEWS_ERROR(SKY, typo, 1, "--set views.doem.image.width=1800: no view 'doem' in the scene (its views: dome, panorama)");
    EXPECT_VIEWS_ERROR(MODEL, typo, 1, "no view 'doem' in the scene (it has no views)");
    /* ...but a whole view may be added. */
    const char *add[] = {"views.pano2={camera: {projection: equirectangular}, image: {width: 360, height: 180}}"};
    EXPECT_VIEWS_OK(SKY, add, 1);
    CHECK(g_views->n == 3 && strcmp(g_views->name[2], "pano2") == 0);
    CHECK(g_views->view[2].projection.kind == ORR_PROJ_EQUIRECTANGULAR && g_views->view[2].projection.width == 360);
    /* Views may not change input.* or observer.*, from --set either. */
    const char *input[] = {"views.dome.input.model.seed=3"};
    EXPECT_VIEWS_ERROR(SKY, input, 1, "--set views.dome.input.model.seed=3: views.dome.input: a view may not set input.*");
    /* Errors in a view's keys name the view. */
    const char *bad[] = {"views.panorama.camera.dome_fov=20"};
    EXPECT_VIEWS_ERROR(SKY, bad, 1, "--set views.panorama.camera.dome_fov=20: camera.dome_fov: 20 is out of range",
                       "(view 'panorama')");
    set_domes(NULL);
}

static void test_view_errors(void)
{
    EXPECT_VIEWS_ERROR(MODEL "views:\n  dome:\n    input:\n      weight: mass\n", NULL, 0,
                       "sky.yaml:6: views.dome.input: a view may not set input.*: all views are rendered from one "
                       "pass over the same particles");
    EXPECT_VIEWS_ERROR(MODEL "observer: {id: 1, reference_id: 2}\nviews:\n  a:\n    observer: {dim: false}\n", NULL, 0,
                       "sky.yaml:7: views.a.observer: a view may not set observer.*");
    EXPECT_VIEWS_ERROR(MODEL "views:\n  a:\n    views: {b: {}}\n", NULL, 0, "views.a.views: a view may not set views.*");
    EXPECT_VIEWS_ERROR(MODEL "views:\n  a:\n    camera:\n      fov: 10\n      fov: 20\n", NULL, 0,
                       "sky.yaml:8: duplicate key 'views.a.camera.fov' (first set at line 7)");
    EXPECT_VIEWS_ERROR(MODEL "views:\n  a: {}\n  a: {}\n", NULL, 0, "sky.yaml:6: duplicate view 'views.a' (first set at line 5)");
    EXPECT_VIEWS_ERROR(MODEL "views:\n  'a b': {}\n", NULL, 0, "sky.yaml:5: views: 'a b' is not a view name");
    EXPECT_VIEWS_ERROR(MODEL "views:\n  a/b: {}\n", NULL, 0, "'a/b' is not a view name");
    EXPECT_VIEWS_ERROR(MODEL "views:\n  a: 5\n", NULL, 0, "sky.yaml:5: views.a: expected a mapping of scene keys, got '5'");
    EXPECT_VIEWS_ERROR(MODEL "views: [a, b]\n", NULL, 0, "sky.yaml:4: views: expected a mapping from view names");
    EXPECT_VIEWS_ERROR(MODEL "views:\n  a: {camera: {fov: 200}}\n", NULL, 0,
                       "sky.yaml:5: camera.fov: 200 is out of range", "(view 'a')");
    EXPECT_VIEWS_ERROR(MODEL "views:\n  a: {camera: {fvo: 20}}\n", NULL, 0,
                       "sky.yaml:5: unknown key 'camera.fvo' (did you mean 'camera.fov'?) (view 'a')");
    /* A bad key of the base scene is reported (once, for the first view). */
    EXPECT_VIEWS_ERROR(MODEL "deposit: tsc\nviews:\n  a: {}\n", NULL, 0, "sky.yaml:4: deposit: expected one of");
    /* At most ORR_SCENE_MAX_VIEWS. */
    char yaml[512];
    snprintf(yaml, sizeof yaml, "%s", MODEL "views:\n");
    for (int i = 0; i <= ORR_SCENE_MAX_VIEWS; i++) {
        size_t len = strlen(yaml);
        snprintf(yaml + len, sizeof yaml - len, "  v%d: {}\n", i);
    }
    EXPECT_VIEWS_ERROR(yaml, NULL, 0, "sky.yaml:4: views: 9 views; a scene has at most 8");
}

static void test_view_merging(void)
{
    /* Mappings merge key by key; scalars and lists replace; an empty
     * section or view changes nothing. */
    EXPECT_VIEWS_OK(MODEL "camera:\n  position: [0, 0, 5]\n  up: [0, 0, 1]\nimage: {width: 300, height: 200}\n"
                          "views:\n"
                          "  a:\n    camera: {position: [1, 2, 3]}\n    image: {height: 100}\n"
                          "  b:\n    camera:\n"
                          "  c:\n",
                    NULL, 0);
    const orr_scene *a = &g_views->view[0], *b = &g_views->view[1], *c = &g_views->view[2];
    CHECK(a->camera.position.x == 1 && a->camera.position.z == 3 && a->camera.has_up && a->camera.up.z == 1);
    CHECK(a->projection.width == 300 && a->projection.height == 100);
    CHECK(b->camera.position.z == 5 && b->projection.height == 200);
    CHECK(c->camera.position.z == 5 && strcmp(c->output.name, "sky-c") == 0);
}

static void test_no_views(void)
{
    /* A scene without views is one unnamed view. */
    EXPECT_VIEWS_OK(MODEL "deposit: ngp\n", NULL, 0);
    CHECK(g_views->n == 1 && g_views->name[0][0] == '\0');
    CHECK(strcmp(g_views->view[0].output.name, "sky") == 0 && g_views->view[0].deposit.kind == ORR_DEPOSIT_NGP);
    /* So is one whose views: is empty. */
    EXPECT_VIEWS_OK(MODEL "views:\n  # dome: {}\n", NULL, 0);
    CHECK(g_views->n == 1 && g_views->name[0][0] == '\0' && strcmp(g_views->view[0].output.name, "sky") == 0);
    EXPECT_VIEWS_OK(MODEL "views: {}\n", NULL, 0);
    CHECK(g_views->n == 1);
}

static void test_single_loaders(void)
{
    orr_error err;
    /* One view: the single loaders return it. */
    CHECK(load_one(MODEL "views:\n  pano: {camera: {projection: equirectangular}}\n", NULL, 0, &err) == ORR_OK);
    CHECK(g_scene.projection.kind == ORR_PROJ_EQUIRECTANGULAR && strcmp(g_scene.output.name, "sky-pano") == 0);
    /* Several: an error pointing to the views loader. */
    CHECK(load_one(MODEL "views:\n  a: {}\n  b: {}\n", NULL, 0, &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "sky.yaml: the scene has 2 views (a, b) but was loaded as a single scene");
    CHECK_CONTAINS(err.msg, "orr_scene_load_views");

    /* From a file. */
    char path[256];
    write_tmp("future.yaml", MODEL "views:\n  a: {deposit: ngp}\n  b: {image: {width: 64}}\n");
    orr_scene_views_free(g_views);
    CHECK(orr_scene_load_views(g_views, tmp_path(path, sizeof path, "future.yaml"), NULL, 0, &err) == ORR_OK);
    CHECK(g_views->n == 2 && strcmp(g_views->view[1].output.name, "future-b") == 0);
    CHECK(g_views->view[1].projection.width == 64 && strcmp(g_views->view[0].dir, g_tmp) == 0);
    orr_scene_free(&g_scene);
    CHECK(orr_scene_load(&g_scene, path, NULL, 0, &err) == ORR_ERR_USAGE);
    remove_tmp("future.yaml");
    orr_scene_views_free(g_views);
    CHECK(orr_scene_load_views(g_views, path, NULL, 0, &err) == ORR_ERR_IO);
    CHECK_CONTAINS(err.msg, "cannot open scene file");
}

int main(void)
{
    g_views = calloc(1, sizeof *g_views);
    snprintf(g_tmp, sizeof g_tmp, "/tmp/orrery_views_XXXXXX");
    if (!g_views || !mkdtemp(g_tmp)) {
        fprintf(stderr, "cannot set up: no memory or no temporary folder\n");
        return 1;
    }
    RUN(test_repo_profiles);
    RUN(test_profile_search);
    RUN(test_bad_profiles);
    RUN(test_profile_precedence);
    RUN(test_two_views);
    RUN(test_view_output_names);
    RUN(test_view_overrides);
    RUN(test_view_errors);
    RUN(test_view_merging);
    RUN(test_no_views);
    RUN(test_single_loaders);
    CHECK(rmdir(g_tmp) == 0);
    orr_scene_views_free(g_views);
    free(g_views);
    return check_summary();
}
