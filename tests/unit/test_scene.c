/* Scene files: defaults, every key, path resolution, --set overrides, and the
 * message and code of each kind of bad input. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "check.h"
#include "scene/scene.h"
#include "scene/scene_output.h"

/* Scenes are large (several path buffers); one shared copy keeps the stack small. */
static orr_scene g_scene;

/* The smallest valid scene: the built-in model with every default. */
#define MODEL "input:\n  model:\n    name: mw-m31\n"
/* The same, open for more input.* keys (which start on line 3). */
#define MODEL_INPUT "input:\n  model: {name: mw-m31}\n"

static orr_status load(const char *yaml, const char *const *sets, int nsets, orr_error *err)
{
    orr_error_clear(err);
    orr_scene_free(&g_scene);
    return orr_scene_load_string(&g_scene, yaml, "scene.yaml", "/base", sets, nsets, err);
}

/* Loads yaml (with optional overrides) and checks the error code and that the
 * message contains each of the given fragments. */
#define EXPECT_ERROR_SETS(yaml, sets, nsets, code, ...)                                   \
    do {                                                                                  \
        orr_error e_;                                                                     \
        orr_status st_ = load((yaml), (sets), (nsets), &e_);                              \
        CHECK(st_ == (code));                                                             \
        if (st_ != (code))                                                                \
            fprintf(stderr, "  got status %d: %s\n", (int)st_, e_.msg);                   \
        const char *needles_[] = {__VA_ARGS__};                                           \
        for (size_t i_ = 0; i_ < sizeof needles_ / sizeof needles_[0]; i_++)              \
            CHECK_CONTAINS(e_.msg, needles_[i_]);                                         \
    } while (0)
#define EXPECT_ERROR(yaml, code, ...) EXPECT_ERROR_SETS(yaml, NULL, 0, code, __VA_ARGS__)

/* Loads yaml and checks that it succeeds, printing the message when not. */
#define EXPECT_OK(yaml, sets, nsets)                                    \
    do {                                                                \
        orr_error e_;                                                   \
        orr_status st_ = load((yaml), (sets), (nsets), &e_);            \
        CHECK(st_ == ORR_OK);                                           \
        if (st_ != ORR_OK)                                              \
            fprintf(stderr, "  unexpected error: %s\n", e_.msg);        \
    } while (0)

static void test_defaults(void)
{
    orr_scene *s = &g_scene;
    orr_scene_free(s);
    CHECK(orr_scene_defaults(s, NULL) == ORR_OK);
    CHECK(strcmp(s->path, "<built-in>") == 0);
    CHECK(strcmp(s->dir, ".") == 0);
    CHECK(s->input.file == NULL); /* unset: NULL (core/owned.h) */
    CHECK(strcmp(s->input.format, "auto") == 0);
    CHECK(s->input.model.name[0] == '\0');
    CHECK(s->input.model.particles == 200000);
    CHECK(s->input.model.seed == 1);
    CHECK(s->input.model.separation == 780);
    CHECK(s->input.model.galaxies == 0); /* ORR_MODEL_PAIR */
    CHECK(s->input.model.disc_q == 1.5);
    CHECK(strcmp(s->input.weight, "mass") == 0);
    CHECK(s->input.type_mask == 0x3f);
    CHECK(s->input.chunk_size == 1048576);
    CHECK(s->input.skip_nonfinite == 0);
    CHECK(s->camera.position.x == 0 && s->camera.position.y == 0 && s->camera.position.z == 0);
    CHECK(!s->camera.has_look_at && !s->camera.has_direction && !s->camera.has_quaternion && !s->camera.has_up);
    CHECK(s->camera.up.x == 0 && s->camera.up.y == 1 && s->camera.up.z == 0);
    CHECK(s->camera.roll == 0);
    CHECK(s->projection.kind == ORR_PROJ_ORTHOGRAPHIC);
    CHECK(s->projection.width == 1024 && s->projection.height == 1024);
    CHECK(s->projection.ortho_width == 100);
    CHECK(s->projection.fov_deg == 60);
    CHECK(s->projection.near == 1e-3);
    CHECK(s->deposit.kind == ORR_DEPOSIT_CIC);
    CHECK(strcmp(s->output.dir, ".") == 0);
    CHECK(s->output.write_fits == 1 && s->output.write_png == 1);
    CHECK(s->output.png_bits == 8);
    CHECK(s->picture.stretch.kind == ORR_STRETCH_LOG);
    CHECK(s->picture.stretch.white == 0);
    CHECK(s->picture.stretch.white_percentile == 99.9);
    CHECK(s->picture.stretch.n == 1000);
    CHECK(s->picture.colormap == ORR_CMAP_MAGMA);
    CHECK(strcmp(s->output.bunit, "") == 0 && strcmp(s->output.length_unit, "") == 0);

    /* A minimal scene keeps them, and names the output after the scene. */
    EXPECT_OK(MODEL, NULL, 0);
    CHECK(strcmp(g_scene.input.model.name, "mw-m31") == 0);
    CHECK(g_scene.input.model.particles == 200000);
    CHECK(g_scene.projection.width == 1024);
    CHECK(strcmp(g_scene.output.name, "scene") == 0);
    CHECK(strcmp(g_scene.path, "scene.yaml") == 0);
    CHECK(strcmp(g_scene.dir, "/base") == 0);
}

static void test_full_scene(void)
{
    const char *yaml = "# every key but input.file, camera.look_at and camera.direction\n"
                       "input:\n"
                       "  format: text\n"
                       "  model:\n"
                       "    name: mw-m31\n"
                       "    particles: 2e6\n"
                       "    seed: 42\n"
                       "    separation: 700.5\n"
                       "    galaxies: m31\n"
                       "    disc_q: 2.5\n"
                       "  weight: luminosity\n"
                       "  types: [0, 2, 4]\n"
                       "  chunk: 65536\n"
                       "  nonfinite: skip\n"
                       "camera:\n"
                       "  position: [1, -2.5, 3e2]\n"
                       "  up: [0, 0, 1]\n"
                       "  roll: -15\n"
                       "  quaternion: [0, 0, 0, 2]   # normalised on load\n"
                       "  projection: perspective\n"
                       "  width: 250\n"
                       "  fov: 45\n"
                       "  near: 0.5\n"
                       "image: {width: 800, height: 600}\n"
                       "deposit: ngp\n"
                       "output:\n"
                       "  dir: renders/out\n"
                       "  name: galaxy\n"
                       "  fits: no\n"
                       "  png: on\n"
                       "  png_bits: 16\n"
                       "  stretch: asinh\n"
                       "  white: 3.5\n"
                       "  white_percentile: 99.5\n"
                       "  softening: 50\n"
                       "  colormap: gray\n"
                       "  bunit: 'Msun'\n";
    EXPECT_OK(yaml, NULL, 0);
    const orr_scene *s = &g_scene;
    CHECK(strcmp(s->input.format, "text") == 0);
    CHECK(strcmp(s->input.model.name, "mw-m31") == 0);
    CHECK(s->input.model.particles == 2000000);
    CHECK(s->input.model.seed == 42);
    CHECK(s->input.model.separation == 700.5);
    CHECK(s->input.model.galaxies == 2); /* ORR_MODEL_M31 */
    CHECK(s->input.model.disc_q == 2.5);
    CHECK(strcmp(s->input.weight, "luminosity") == 0);
    CHECK(s->input.type_mask == ((1u << 0) | (1u << 2) | (1u << 4)));
    CHECK(s->input.chunk_size == 65536);
    CHECK(s->input.skip_nonfinite == 1);
    CHECK(s->camera.position.x == 1 && s->camera.position.y == -2.5 && s->camera.position.z == 300);
    CHECK(s->camera.has_up && s->camera.up.z == 1 && s->camera.up.y == 0);
    CHECK(s->camera.roll == -15);
    CHECK(s->camera.has_quaternion && !s->camera.has_look_at && !s->camera.has_direction);
    CHECK(s->camera.quaternion.w == 0 && s->camera.quaternion.z == 1);
    CHECK(s->projection.kind == ORR_PROJ_PERSPECTIVE);
    CHECK(s->projection.ortho_width == 250);
    CHECK(s->projection.fov_deg == 45);
    CHECK(s->projection.near == 0.5);
    CHECK(s->projection.width == 800 && s->projection.height == 600);
    CHECK(s->deposit.kind == ORR_DEPOSIT_NGP);
    CHECK(strcmp(s->output.dir, "renders/out") == 0); /* not resolved against the scene */
    CHECK(strcmp(s->output.name, "galaxy") == 0);
    CHECK(s->output.write_fits == 0 && s->output.write_png == 1);
    CHECK(s->output.png_bits == 16);
    CHECK(s->picture.stretch.kind == ORR_STRETCH_ASINH);
    CHECK(s->picture.stretch.white == 3.5);
    CHECK(s->picture.stretch.white_percentile == 99.5);
    CHECK(s->picture.stretch.n == 50);
    CHECK(s->picture.colormap == ORR_CMAP_GREY);
    CHECK(strcmp(s->output.bunit, "Msun") == 0);
}

static void test_camera_orientations(void)
{
    EXPECT_OK(MODEL "camera:\n  position: [0, 0, 10]\n  look_at: [1, 2, 3]\n", NULL, 0);
    CHECK(g_scene.camera.has_look_at && !g_scene.camera.has_direction && !g_scene.camera.has_up);
    CHECK(g_scene.camera.look_at.x == 1 && g_scene.camera.look_at.z == 3);
    EXPECT_OK(MODEL "camera:\n  direction: [0, -1, 0]\n  up: [0, 0, 1]\n", NULL, 0);
    CHECK(g_scene.camera.has_direction && g_scene.camera.has_up && g_scene.camera.direction.y == -1);
    /* "camera:" with every key commented out is an empty section, not an error. */
    EXPECT_OK(MODEL "camera:\n  # look_at: [0, 0, 0]\n", NULL, 0);
    CHECK(!g_scene.camera.has_look_at);
    /* white: auto is 0, the automatic white level. */
    EXPECT_OK(MODEL "output:\n  white: auto\n", NULL, 0);
    CHECK(g_scene.picture.stretch.white == 0);
    /* One type alone needs no list; booleans in their other spellings. */
    EXPECT_OK(MODEL_INPUT "  types: 3\noutput: {fits: off, png: Yes}\n", NULL, 0);
    CHECK(g_scene.input.type_mask == 8u && g_scene.output.write_fits == 0 && g_scene.output.write_png == 1);
}

static int write_text(const char *path, const char *text)
{
    FILE *f = fopen(path, "w");
    if (!f)
        return 0;
    int ok = fputs(text, f) >= 0;
    return fclose(f) == 0 && ok;
}

static void test_file_paths(void)
{
    char dir[] = "/tmp/orrery_scene_XXXXXX";
    if (!mkdtemp(dir)) {
        CHECK(!"mkdtemp failed");
        return;
    }
    char scene[256], abs_scene[256], bad[256];
    snprintf(scene, sizeof scene, "%s/face-on.view.yaml", dir);
    snprintf(abs_scene, sizeof abs_scene, "%s/absolute.yaml", dir);
    snprintf(bad, sizeof bad, "%s/bad.yaml", dir);
    CHECK(write_text(scene, "input:\n  file: data/snap.txt\noutput:\n  dir: out\n"));
    CHECK(write_text(abs_scene, "input:\n  file: /data/snap.txt\n"));
    CHECK(write_text(bad, "input:\n  file: snap.txt\n\ncamera:\n  fov: sixty\n"));

    orr_error err;
    orr_scene_free(&g_scene);
    orr_status st = orr_scene_load(&g_scene, scene, NULL, 0, &err);
    CHECK(st == ORR_OK);
    char want[512];
    snprintf(want, sizeof want, "%s/data/snap.txt", dir);
    CHECK(strcmp(g_scene.input.file, want) == 0);
    CHECK(strcmp(g_scene.dir, dir) == 0);
    CHECK(strcmp(g_scene.path, scene) == 0);
    CHECK(strcmp(g_scene.output.dir, "out") == 0);          /* against the working directory */
    CHECK(strcmp(g_scene.output.name, "face-on.view") == 0); /* the stem drops only the last extension */
    CHECK(g_scene.input.model.name[0] == '\0');

    orr_scene_free(&g_scene);

    st = orr_scene_load(&g_scene, abs_scene, NULL, 0, &err);
    CHECK(st == ORR_OK);
    CHECK(strcmp(g_scene.input.file, "/data/snap.txt") == 0);

    /* Errors from a file name the file as given and the line. */
    orr_scene_free(&g_scene);
    st = orr_scene_load(&g_scene, bad, NULL, 0, &err);
    CHECK(st == ORR_ERR_USAGE);
    snprintf(want, sizeof want, "%s:5: camera.fov: expected a number, got 'sixty'", bad);
    CHECK(strcmp(err.msg, want) == 0);

    /* A --set path was typed in a shell: it stays relative to the working directory. */
    const char *sets[] = {"input.file=other.txt"};
    orr_scene_free(&g_scene);
    st = orr_scene_load(&g_scene, scene, sets, 1, &err);
    CHECK(st == ORR_OK);
    CHECK(strcmp(g_scene.input.file, "other.txt") == 0);

    remove(scene);
    remove(abs_scene);
    remove(bad);
    CHECK(rmdir(dir) == 0);
}

static void test_missing_file(void)
{
    orr_error err;
    orr_scene_free(&g_scene);
    orr_status st = orr_scene_load(&g_scene, "/nonexistent/dir/scene.yaml", NULL, 0, &err);
    CHECK(st == ORR_ERR_IO);
    CHECK(strcmp(err.msg, "/nonexistent/dir/scene.yaml: cannot open scene file: No such file or directory") == 0);
}

static void test_load_string_names(void)
{
    orr_error err;
    /* A relative file in a scene from memory is resolved against base_dir. */
    orr_scene_free(&g_scene);
    CHECK(orr_scene_load_string(&g_scene, "input: {file: a.txt}", "builtin/ortho.yaml", "/srv/data", NULL, 0,
                                &err) == ORR_OK);
    CHECK(strcmp(g_scene.input.file, "/srv/data/a.txt") == 0);
    CHECK(strcmp(g_scene.output.name, "ortho") == 0);
    /* No base folder: the path stays as written; no origin: output "orrery". */
    orr_scene_free(&g_scene);
    CHECK(orr_scene_load_string(&g_scene, "input: {file: a.txt}", NULL, NULL, NULL, 0, &err) == ORR_OK);
    CHECK(strcmp(g_scene.input.file, "a.txt") == 0);
    CHECK(strcmp(g_scene.output.name, "orrery") == 0);
    CHECK(strcmp(g_scene.path, "<built-in>") == 0);
    /* "-" is standard input, not a file beside the scene. */
    orr_scene_free(&g_scene);
    CHECK(orr_scene_load_string(&g_scene, "input: {file: \"-\"}", "builtin/ortho.yaml", "/srv/data", NULL, 0,
                                &err) == ORR_OK);
    CHECK(strcmp(g_scene.input.file, "-") == 0);
    /* Messages name the origin given. */
    orr_scene_free(&g_scene);
    CHECK(orr_scene_load_string(&g_scene, "deposit: tsc\n", "face-on", NULL, NULL, 0, &err) == ORR_ERR_USAGE);
    CHECK(strcmp(err.msg, "face-on:1: deposit: expected one of: ngp cic sph, got 'tsc'") == 0);
}

static void test_overrides(void)
{
    const char *yaml = MODEL "camera:\n  look_at: [0, 0, 0]\n  position: [0, 0, 5]\nimage:\n  width: 640\n";
    const char *sets[] = {
        "image.width=320",                  /* replace a scalar */
        "camera.position=[0, 0, 10]",       /* a list */
        "input.types=[2,3]",                /* a list of types */
        "output.colormap=inferno",          /* a key the file does not have */
        "camera.projection = perspective",  /* spaces around '=' */
        "output.name=view-1",
    };
    EXPECT_OK(yaml, sets, 6);
    CHECK(g_scene.projection.width == 320);
    CHECK(g_scene.projection.height == 1024);
    CHECK(g_scene.camera.position.z == 10);
    CHECK(g_scene.camera.has_look_at);
    CHECK(g_scene.input.type_mask == ((1u << 2) | (1u << 3)));
    CHECK(g_scene.picture.colormap == ORR_CMAP_INFERNO);
    CHECK(g_scene.projection.kind == ORR_PROJ_PERSPECTIVE);
    CHECK(strcmp(g_scene.output.name, "view-1") == 0);

    /* Replacing a whole mapping drops the keys it had (here look_at), so a
     * direction no longer conflicts with it. */
    const char *replace[] = {"camera={direction: [1, 0, 0], up: [0, 0, 1]}"};
    EXPECT_OK(yaml, replace, 1);
    CHECK(g_scene.camera.has_direction && !g_scene.camera.has_look_at);
    CHECK(g_scene.camera.position.z == 0);

    /* Later overrides win; a mapping is made where a scalar was. */
    const char *later[] = {"image.width=100", "image.width=200", "deposit=ngp"};
    EXPECT_OK(yaml, later, 3);
    CHECK(g_scene.projection.width == 200);
    CHECK(g_scene.deposit.kind == ORR_DEPOSIT_NGP);
    const char *remap[] = {"image=5", "image.height=7"};
    EXPECT_OK(yaml, remap, 2);
    CHECK(g_scene.projection.height == 7 && g_scene.projection.width == 1024);

    /* Overrides can supply keys a file lacks entirely. */
    const char *input[] = {"input.model.name=mw-m31", "input.model.particles=1000"};
    EXPECT_OK("deposit: cic\n", input, 2);
    CHECK(g_scene.input.model.particles == 1000);
}

static void test_bad_overrides(void)
{
    const char *no_eq[] = {"image.width"};
    EXPECT_ERROR_SETS(MODEL, no_eq, 1, ORR_ERR_USAGE, "--set image.width: expected key=value");
    const char *empty_key[] = {"=5"};
    EXPECT_ERROR_SETS(MODEL, empty_key, 1, ORR_ERR_USAGE, "--set =5: the key before '=' is empty");
    const char *empty_part[] = {"camera..fov=5"};
    EXPECT_ERROR_SETS(MODEL, empty_part, 1, ORR_ERR_USAGE, "--set camera..fov=5:", "empty part");
    const char *trailing[] = {"camera.=5"};
    EXPECT_ERROR_SETS(MODEL, trailing, 1, ORR_ERR_USAGE, "empty part");

    orr_error err;
    const char *range[] = {"image.width=-5"};
    CHECK(load(MODEL, range, 1, &err) == ORR_ERR_USAGE);
    CHECK(strcmp(err.msg, "--set image.width=-5: image.width: -5 is out of range (1 to 65536)") == 0);

    const char *syntax[] = {"camera.position=[0, 0"};
    EXPECT_ERROR_SETS(MODEL, syntax, 1, ORR_ERR_USAGE, "--set camera.position=[0, 0: YAML syntax error:");
    const char *unknown[] = {"camera.fvo=30"};
    EXPECT_ERROR_SETS(MODEL, unknown, 1, ORR_ERR_USAGE,
                      "--set camera.fvo=30: unknown key 'camera.fvo' (did you mean 'camera.fov'?)");
    const char *novalue[] = {"camera.fov="};
    EXPECT_ERROR_SETS(MODEL, novalue, 1, ORR_ERR_USAGE, "--set camera.fov=: camera.fov: expected a number, got nothing");
    const char *badlist[] = {"camera.position=[0, x, 1]"};
    EXPECT_ERROR_SETS(MODEL, badlist, 1, ORR_ERR_USAGE,
                      "--set camera.position=[0, x, 1]: camera.position[1]: expected a number, got 'x'");
}

static void test_yaml_errors(void)
{
    /* libyaml's own messages, with line and column. */
    EXPECT_ERROR(MODEL "camera:\n  position: [0, 0\n  roll: 1\n", ORR_ERR_USAGE, "scene.yaml:", "YAML syntax error: ");
    EXPECT_ERROR("input:\n  file: a\n   bad: 1\n", ORR_ERR_USAGE, "scene.yaml:3:7:", "YAML syntax error: ",
                 "mapping values are not allowed");
    EXPECT_ERROR("a: 'unclosed\n", ORR_ERR_USAGE, "YAML syntax error");
    EXPECT_ERROR("input:\n\tfile: a\n", ORR_ERR_USAGE, "scene.yaml:2:1: YAML syntax error: ", "not tabs");
    /* Empty documents. */
    EXPECT_ERROR("", ORR_ERR_USAGE, "scene.yaml: the scene is empty");
    EXPECT_ERROR("# nothing but a comment\n\n", ORR_ERR_USAGE, "scene.yaml: the scene is empty");
    EXPECT_ERROR("---\n", ORR_ERR_USAGE, "scene.yaml: the scene is empty");
    /* The top level must be a mapping. */
    EXPECT_ERROR("- input\n- camera\n", ORR_ERR_USAGE, "scene.yaml:1: the top level of a scene must be a mapping",
                 "a list");
    EXPECT_ERROR("just words\n", ORR_ERR_USAGE, "the top level of a scene must be a mapping", "'just words'");
    /* One document only; no aliases; no complex keys. */
    EXPECT_ERROR(MODEL "---\ndeposit: ngp\n", ORR_ERR_USAGE, "scene.yaml:4: a scene is one YAML document");
    EXPECT_ERROR(MODEL "camera:\n  position: &p [0, 0, 1]\n  look_at: *p\n", ORR_ERR_USAGE, "scene.yaml:6:",
                 "aliases (*p) are not supported");
    EXPECT_ERROR("? [a, b]\n: c\n", ORR_ERR_USAGE, "scene.yaml:1: keys must be plain words");
}

static void test_key_errors(void)
{
    orr_error err;
    CHECK(load(MODEL "camera:\n  fvo: 30\n", NULL, 0, &err) == ORR_ERR_USAGE);
    CHECK(strcmp(err.msg, "scene.yaml:5: unknown key 'camera.fvo' (did you mean 'camera.fov'?)") == 0);
    EXPECT_ERROR(MODEL "camrea:\n  roll: 3\n", ORR_ERR_USAGE, "scene.yaml:4: unknown key 'camrea' (did you mean 'camera'?)");
    /* No close spelling, but only one key ends the same way. */
    EXPECT_ERROR(MODEL "camera:\n  height: 3\n", ORR_ERR_USAGE,
                 "scene.yaml:5: unknown key 'camera.height' (did you mean 'image.height'?)");
    EXPECT_ERROR(MODEL "colur: red\n", ORR_ERR_USAGE, "scene.yaml:4: unknown key 'colur'");
    EXPECT_ERROR(MODEL "colour: red\n", ORR_ERR_USAGE, "scene.yaml:4: colour: expected a mapping of colour.* keys, got 'red'");
    /* Keys below a leaf are unknown, not silently ignored. */
    EXPECT_ERROR(MODEL "deposit:\n  kind: ngp\n", ORR_ERR_USAGE, "scene.yaml:4: deposit: expected one of: ngp cic sph, got a mapping");
    EXPECT_ERROR(MODEL "image:\n  width: 10\n  height: 10\n  width: 20\n", ORR_ERR_USAGE,
                 "scene.yaml:7: duplicate key 'image.width' (first set at line 5)");
    EXPECT_ERROR(MODEL "camera.roll: 5\n", ORR_ERR_USAGE, "scene.yaml:4: key 'camera.roll' contains a '.'");
    EXPECT_ERROR(MODEL "'': 5\n", ORR_ERR_USAGE, "scene.yaml:4: empty key");
    /* A scalar where a mapping is wanted and the other way round. */
    EXPECT_ERROR(MODEL "camera: 5\n", ORR_ERR_USAGE, "scene.yaml:4: camera: expected a mapping of camera.* keys, got '5'");
    EXPECT_ERROR(MODEL "camera: [1, 2]\n", ORR_ERR_USAGE, "camera: expected a mapping of camera.* keys, got a list");
    EXPECT_ERROR(MODEL "camera:\n  fov:\n    deg: 30\n", ORR_ERR_USAGE,
                 "scene.yaml:5: camera.fov: expected a number, got a mapping");
    EXPECT_ERROR(MODEL "output:\n  name: [a, b]\n", ORR_ERR_USAGE, "scene.yaml:5: output.name: expected a string, got a list");
    EXPECT_ERROR(MODEL "camera:\n  fov:\n", ORR_ERR_USAGE, "scene.yaml:5: camera.fov: expected a number, got nothing");
}

static void test_value_errors(void)
{
    orr_error err;
    CHECK(load(MODEL "camera:\n  projection: perspective\n  fov: sixty\n", NULL, 0, &err) == ORR_ERR_USAGE);
    CHECK(strcmp(err.msg, "scene.yaml:6: camera.fov: expected a number, got 'sixty'") == 0);
    /* Non-finite numbers, in every spelling. */
    EXPECT_ERROR(MODEL "camera:\n  roll: .nan\n", ORR_ERR_USAGE, "scene.yaml:5: camera.roll: expected a finite number, got '.nan'");
    EXPECT_ERROR(MODEL "camera:\n  roll: -.inf\n", ORR_ERR_USAGE, "expected a finite number, got '-.inf'");
    EXPECT_ERROR(MODEL "camera:\n  roll: NaN\n", ORR_ERR_USAGE, "expected a finite number, got 'NaN'");
    EXPECT_ERROR(MODEL "camera:\n  roll: 1e999\n", ORR_ERR_USAGE, "expected a finite number, got '1e999'");
    EXPECT_ERROR(MODEL "camera:\n  position: [0, inf, 0]\n", ORR_ERR_USAGE,
                 "scene.yaml:5: camera.position[1]: expected a finite number, got 'inf'");
    EXPECT_ERROR(MODEL "camera:\n  roll: 0x10\n", ORR_ERR_USAGE, "expected a number, got '0x10'");
    EXPECT_ERROR(MODEL "camera:\n  roll: 1.2.3\n", ORR_ERR_USAGE, "expected a number, got '1.2.3'");
    /* Integers. */
    EXPECT_ERROR(MODEL "image:\n  width: 12abc\n", ORR_ERR_USAGE, "scene.yaml:5: image.width: expected an integer, got '12abc'");
    EXPECT_ERROR(MODEL "image:\n  width: 12.5\n", ORR_ERR_USAGE, "image.width: expected an integer, got '12.5'");
    EXPECT_ERROR(MODEL "image:\n  height: 65537\n", ORR_ERR_USAGE, "image.height: 65537 is out of range (1 to 65536)");
    EXPECT_ERROR(MODEL_INPUT "  chunk: 4294967297\n", ORR_ERR_USAGE, "input.chunk: 4294967297 is out of range (1 to 4294967296)");
    EXPECT_ERROR(MODEL_INPUT "  chunk: 99999999999999999999\n", ORR_ERR_USAGE, "input.chunk: 99999999999999999999 is out of range");
    EXPECT_ERROR("input:\n  model:\n    name: mw-m31\n    seed: -1\n", ORR_ERR_USAGE, "scene.yaml:4: input.model.seed: -1 is out of range (0 to");
    EXPECT_ERROR("input:\n  model:\n    name: mw-m31\n    particles: 50\n", ORR_ERR_USAGE,
                 "input.model.particles: 50 is out of range (100 to 2000000000)");
    /* Number bounds. */
    EXPECT_ERROR(MODEL "camera:\n  width: 0\n", ORR_ERR_USAGE, "scene.yaml:5: camera.width: 0 is out of range (must be > 0)");
    EXPECT_ERROR(MODEL "camera:\n  fov: 180\n", ORR_ERR_USAGE, "camera.fov: 180 is out of range (must be > 0 and < 180)");
    EXPECT_ERROR(MODEL "camera:\n  near: -1\n", ORR_ERR_USAGE, "camera.near: -1 is out of range (must be >= 0)");
    EXPECT_ERROR(MODEL "output:\n  white_percentile: 100.5\n", ORR_ERR_USAGE,
                 "output.white_percentile: 100.5 is out of range (must be > 0 and <= 100)");
    EXPECT_ERROR(MODEL "output:\n  white: -1\n", ORR_ERR_USAGE, "output.white: -1 is out of range (must be > 0)");
    EXPECT_ERROR(MODEL "output:\n  white: bright\n", ORR_ERR_USAGE, "output.white: expected a number or auto, got 'bright'");
    EXPECT_ERROR("input:\n  model:\n    name: mw-m31\n    separation: 0\n", ORR_ERR_USAGE, "input.model.separation: 0 is out of range (must be > 0)");
    EXPECT_ERROR("input:\n  model:\n    name: mw-m31\n    disc_q: 0\n", ORR_ERR_USAGE, "input.model.disc_q: 0 is out of range (must be > 0)");
    EXPECT_ERROR("input:\n  model:\n    name: mw-m31\n    disc_q: -1.5\n", ORR_ERR_USAGE, "input.model.disc_q: -1.5 is out of range (must be > 0)");
    EXPECT_ERROR("input:\n  model:\n    name: mw-m31\n    galaxies: both\n", ORR_ERR_USAGE, "input.model.galaxies: expected one of: pair mw m31, got 'both'");
    EXPECT_ERROR("input:\n  model:\n    name: king\n    galaxies: mw\n", ORR_ERR_USAGE, "input.model.galaxies does not apply to input.model.name: king");
    /* Booleans and words. */
    EXPECT_ERROR(MODEL "output:\n  fits: maybe\n", ORR_ERR_USAGE, "scene.yaml:5: output.fits: expected true or false, got 'maybe'");
    EXPECT_ERROR(MODEL "camera:\n  projection: ortho\n", ORR_ERR_USAGE,
                 "camera.projection: expected one of: orthographic perspective, got 'ortho'");
    EXPECT_ERROR(MODEL "output:\n  colormap: viridis\n", ORR_ERR_USAGE,
                 "output.colormap: expected one of: grey magma inferno, got 'viridis'");
    EXPECT_ERROR(MODEL "output:\n  stretch: sqrt\n", ORR_ERR_USAGE, "output.stretch: expected one of: linear log asinh, got 'sqrt'");
    EXPECT_ERROR(MODEL "output:\n  png_bits: 12\n", ORR_ERR_USAGE, "output.png_bits: expected one of: 8 16, got '12'");
    EXPECT_ERROR(MODEL_INPUT "  nonfinite: drop\n", ORR_ERR_USAGE, "input.nonfinite: expected one of: error skip, got 'drop'");
    EXPECT_ERROR(MODEL_INPUT "  format: fits\n", ORR_ERR_USAGE,
                 "input.format: expected one of: auto hdf5 gadget tipsy npy npz text, got 'fits'");
    EXPECT_ERROR("input:\n  model:\n    name: plummer\n", ORR_ERR_USAGE, "scene.yaml:3: input.model.name: expected one of: mw-m31 king, got 'plummer'");
    /* Strings. */
    EXPECT_ERROR(MODEL "output:\n  name: a/b\n", ORR_ERR_USAGE, "output.name: 'a/b' must be a file name",
                 "(the folder is output.dir)");
    EXPECT_ERROR(MODEL "output:\n  bunit: ''\n", ORR_ERR_USAGE, "scene.yaml:5: output.bunit: must not be empty");
    /* Vectors and types. */
    EXPECT_ERROR(MODEL "camera:\n  position: [1, 2]\n", ORR_ERR_USAGE,
                 "scene.yaml:5: camera.position: expected a list of 3 numbers [x, y, z], got a list of 2");
    EXPECT_ERROR(MODEL "camera:\n  quaternion: 1\n", ORR_ERR_USAGE,
                 "camera.quaternion: expected a list of 4 numbers [w, x, y, z], got '1'");
    EXPECT_ERROR(MODEL "camera:\n  position:\n    - 1\n    - two\n    - 3\n", ORR_ERR_USAGE,
                 "scene.yaml:7: camera.position[1]: expected a number, got 'two'");
    EXPECT_ERROR(MODEL_INPUT "  types: [1, 7]\n", ORR_ERR_USAGE, "scene.yaml:3: input.types[1]: 7 is out of range (0 to 5)");
    EXPECT_ERROR(MODEL_INPUT "  types: []\n", ORR_ERR_USAGE, "input.types: the list is empty");
    EXPECT_ERROR(MODEL_INPUT "  types: {gas: 0}\n", ORR_ERR_USAGE, "input.types: expected a list of particle types 0 to 5, got a mapping");
}

static void test_cross_checks(void)
{
    EXPECT_ERROR("input:\n  file: a.txt\n  model:\n    name: mw-m31\n", ORR_ERR_USAGE,
                 "scene.yaml:4: input.file and input.model.name are both set");
    EXPECT_ERROR("deposit: ngp\n", ORR_ERR_USAGE, "scene.yaml: no input: set input.file or input.model.name");
    EXPECT_ERROR("input:\n  file: a.txt\n  model:\n    seed: 3\n", ORR_ERR_USAGE,
                 "scene.yaml:4: input.model.seed applies to input.model.name");
    EXPECT_ERROR(MODEL "camera:\n  look_at: [0, 0, 0]\n  direction: [0, 0, 1]\n", ORR_ERR_USAGE,
                 "scene.yaml:6: camera.look_at and camera.direction are both set");
    EXPECT_ERROR(MODEL "camera:\n  quaternion: [1, 0, 0, 0]\n  look_at: [0, 0, 0]\n", ORR_ERR_USAGE,
                 "scene.yaml:5: camera.look_at and camera.quaternion are both set");
    EXPECT_ERROR(MODEL "camera:\n  quaternion: [0, 0, 0, 0]\n", ORR_ERR_USAGE,
                 "scene.yaml:5: camera.quaternion: [0, 0, 0, 0] is not a rotation");
    EXPECT_ERROR(MODEL "camera:\n  direction: [0, 0, 0]\n", ORR_ERR_USAGE, "scene.yaml:5: camera.direction: must not be [0, 0, 0]");
    EXPECT_ERROR(MODEL "camera:\n  up: [0, 0, 0]\n", ORR_ERR_USAGE, "camera.up: must not be [0, 0, 0]");
    EXPECT_ERROR(MODEL "camera:\n  position: [1, 2, 3]\n  look_at: [1, 2, 3]\n", ORR_ERR_USAGE,
                 "scene.yaml:6: camera.look_at: equals camera.position");
    EXPECT_ERROR(MODEL "camera:\n  direction: [0, 2, 0]\n  up: [0, -1, 0]\n", ORR_ERR_USAGE,
                 "scene.yaml:6: camera.up: is parallel to the view direction");
    /* The cross-checks see the overrides: one can resolve a conflict by replacing camera. */
    const char *sets[] = {"camera.quaternion=[1,0,0,0]"};
    EXPECT_ERROR_SETS(MODEL "camera:\n  direction: [0, 0, 1]\n", sets, 1, ORR_ERR_USAGE,
                      "--set camera.quaternion=[1,0,0,0]: camera.direction and camera.quaternion are both set");
}

/* ---- the observer-centred sky: projections, dome keys, observer ---- */

/* A scene with an observer; more observer.* keys start on line 7. */
#define OBSERVER MODEL "observer:\n  id: 7\n  reference_id: 9\n"

static void test_sky_defaults(void)
{
    orr_scene *s = &g_scene;
    orr_scene_free(s);
    CHECK(orr_scene_defaults(s, NULL) == ORR_OK);
    CHECK(s->projection.lon_flip == 0);
    CHECK(s->projection.dome_fov_deg == 180);
    CHECK(s->camera.dome[0] == '\0');
    CHECK(s->camera.dome_tilt == 0);
    CHECK(!s->camera.has_zenith && !s->camera.has_front);
    CHECK(s->camera.zenith_lb[0] == 0 && s->camera.zenith_lb[1] == 90);
    CHECK(s->camera.front_lb[0] == 0 && s->camera.front_lb[1] == 0);
    CHECK(!s->observer.has_id && !s->observer.has_normal);
    CHECK(s->observer.normal.x == 0 && s->observer.normal.y == 0 && s->observer.normal.z == 1);
    CHECK(s->observer.normal_types == 0);
    CHECK(s->observer.normal_radius == 30);
    CHECK(s->observer.normal_sign == -1);
    CHECK(s->observer.dim == 1);
    CHECK(s->observer.dim_near == 0.01);
}

static void test_sky_keys(void)
{
    EXPECT_OK(MODEL "camera:\n  projection: hammer-aitoff\n  lon_flip: true\n", NULL, 0);
    CHECK(g_scene.projection.kind == ORR_PROJ_HAMMER_AITOFF && g_scene.projection.lon_flip == 1);
    EXPECT_OK(MODEL "camera: {projection: equirectangular}\nimage: {width: 720, height: 360}\n", NULL, 0);
    CHECK(g_scene.projection.kind == ORR_PROJ_EQUIRECTANGULAR && g_scene.projection.lon_flip == 0);
    EXPECT_OK(MODEL "camera:\n"
                    "  projection: dome\n"
                    "  dome_fov: 210\n"
                    "  dome_tilt: 30\n"
                    "  zenith: [10, 80]\n"
                    "  front: [-45.5, -10]\n",
              NULL, 0);
    const orr_scene *s = &g_scene;
    CHECK(s->projection.kind == ORR_PROJ_DOME);
    CHECK(s->projection.dome_fov_deg == 210);
    CHECK(s->camera.dome_tilt == 30);
    CHECK(s->camera.has_zenith && s->camera.zenith_lb[0] == 10 && s->camera.zenith_lb[1] == 80);
    CHECK(s->camera.has_front && s->camera.front_lb[0] == -45.5 && s->camera.front_lb[1] == -10);
    /* The bounds are inclusive; l is any finite number (it wraps). */
    EXPECT_OK(MODEL "camera: {projection: dome, dome_fov: 360, dome_tilt: 90, zenith: [720, -90]}\n", NULL, 0);
    CHECK(g_scene.projection.dome_fov_deg == 360 && g_scene.camera.dome_tilt == 90 && g_scene.camera.zenith_lb[0] == 720);
    EXPECT_OK(MODEL "camera: {projection: dome, dome_fov: 90, dome_tilt: 0}\n", NULL, 0);
    /* Dome keys with another projection are checked, and otherwise ignored. */
    EXPECT_OK(MODEL "camera: {projection: perspective, dome_fov: 200, lon_flip: yes}\n", NULL, 0);
    CHECK(g_scene.projection.kind == ORR_PROJ_PERSPECTIVE && g_scene.projection.dome_fov_deg == 200);
    const char *sets[] = {"camera.projection=dome", "camera.zenith=[30, 45]"};
    EXPECT_OK(MODEL, sets, 2);
    CHECK(g_scene.projection.kind == ORR_PROJ_DOME && g_scene.camera.zenith_lb[1] == 45);
}

static void test_sky_key_errors(void)
{
    orr_error err;
    CHECK(load(MODEL "camera:\n  projection: fisheye\n", NULL, 0, &err) == ORR_ERR_USAGE);
    CHECK(strcmp(err.msg, "scene.yaml:5: camera.projection: expected one of: orthographic perspective, got "
                          "'fisheye' (sky maps: hammer-aitoff dome equirectangular healpix)") == 0);
    EXPECT_ERROR(MODEL "camera:\n  dome_fov: 89\n", ORR_ERR_USAGE, "scene.yaml:5: camera.dome_fov: 89 is out of range (90 to 360)");
    EXPECT_ERROR(MODEL "camera:\n  dome_fov: 360.5\n", ORR_ERR_USAGE, "camera.dome_fov: 360.5 is out of range (90 to 360)");
    EXPECT_ERROR(MODEL "camera:\n  dome_tilt: -1\n", ORR_ERR_USAGE, "camera.dome_tilt: -1 is out of range (0 to 90)");
    EXPECT_ERROR(MODEL "camera:\n  dome_tilt: 91\n", ORR_ERR_USAGE, "camera.dome_tilt: 91 is out of range (0 to 90)");
    EXPECT_ERROR(MODEL "camera:\n  lon_flip: left\n", ORR_ERR_USAGE, "scene.yaml:5: camera.lon_flip: expected true or false, got 'left'");
    EXPECT_ERROR(MODEL "camera:\n  dome: domes/flat-180\n", ORR_ERR_USAGE, "camera.dome: 'domes/flat-180' must be a file name",
                 "(a dome profile's name, e.g. flat-180");
    /* Both would write NAME.exr, the picture over the linear planes. */
    EXPECT_ERROR(MODEL "output:\n  exr: true\n  image: EXR\n", ORR_ERR_USAGE,
                 "output.exr: true and output.image: EXR both write NAME.exr");
    EXPECT_OK(MODEL "output:\n  exr: true\n  image: tif\n", NULL, 0);
    /* A NaN count is not a number, not an out-of-range one. */
    EXPECT_ERROR(MODEL "animation:\n  frames: .nan\n", ORR_ERR_USAGE,
                 "animation.frames: expected an integer, got '.nan', which is not a number");
    EXPECT_ERROR(MODEL "image:\n  width: nan\n", ORR_ERR_USAGE, "image.width: expected an integer, got 'nan', which is not a number");
    EXPECT_ERROR(MODEL "output:\n  image: a/tif\n", ORR_ERR_USAGE, "output.image: 'a/tif' must be a file name",
                 "(a file extension such as tif");
    EXPECT_ERROR(MODEL "camera:\n  dome: ''\n", ORR_ERR_USAGE, "camera.dome: must not be empty");
    CHECK(load(MODEL "camera:\n  zenith: [0, 91]\n", NULL, 0, &err) == ORR_ERR_USAGE);
    CHECK(strcmp(err.msg, "scene.yaml:5: camera.zenith[1]: 91 is out of range (-90 to 90: b is a latitude)") == 0);
    EXPECT_ERROR(MODEL "camera:\n  front:\n    - 0\n    - -90.5\n", ORR_ERR_USAGE,
                 "scene.yaml:7: camera.front[1]: -90.5 is out of range (-90 to 90");
    EXPECT_ERROR(MODEL "camera:\n  zenith: [0]\n", ORR_ERR_USAGE,
                 "camera.zenith: expected a list of 2 numbers [l, b] in degrees, got a list of 1");
    EXPECT_ERROR(MODEL "camera:\n  front: [.nan, 0]\n", ORR_ERR_USAGE, "camera.front[0]: expected a finite number, got '.nan'");
    EXPECT_ERROR(MODEL "camera:\n  front: 45\n", ORR_ERR_USAGE, "camera.front: expected a list of 2 numbers [l, b] in degrees, got '45'");
    EXPECT_ERROR(MODEL "camera:\n  domefov: 180\n", ORR_ERR_USAGE, "unknown key 'camera.domefov' (did you mean 'camera.dome_fov'?)");
}

static void test_zenith_front(void)
{
    /* The zenith on the default front [0, 0]: the error names the key that was set. */
    EXPECT_ERROR(MODEL "camera:\n  projection: dome\n  zenith: [0, 0]\n", ORR_ERR_USAGE,
                 "scene.yaml:6: camera.front [0, 0] and camera.zenith [0, 0] are the same direction",
                 "the front is projected perpendicular to the zenith");
    EXPECT_ERROR(MODEL "camera:\n  front: [123, 90]\n", ORR_ERR_USAGE, "scene.yaml:5: camera.front [123, 90]",
                 "the same direction");
    EXPECT_ERROR(MODEL "camera:\n  front: [0, -90]\n", ORR_ERR_USAGE, "opposite directions");
    EXPECT_ERROR(MODEL "camera:\n  zenith: [370, 0]\n  front: [10, 0]\n", ORR_ERR_USAGE, "scene.yaml:6: camera.front");
    /* Within 1e-6 degree is parallel; 1e-5 degree is not. */
    EXPECT_ERROR(MODEL "camera:\n  front: [0, 89.9999999]\n", ORR_ERR_USAGE, "camera.front");
    EXPECT_OK(MODEL "camera:\n  front: [0, 89.99999]\n", NULL, 0);
    EXPECT_OK(MODEL "camera:\n  zenith: [90, 0]\n  front: [0, 0]\n", NULL, 0);
}

static void test_observer_keys(void)
{
    EXPECT_OK(OBSERVER, NULL, 0);
    const orr_scene *s = &g_scene;
    CHECK(s->observer.has_id && s->observer.id == 7 && s->observer.reference_id == 9);
    CHECK(!s->observer.has_normal && s->observer.normal.z == 1 && s->observer.normal_types == 0);
    CHECK(s->observer.normal_radius == 30 && s->observer.normal_sign == -1 && s->observer.dim == 1 && s->observer.dim_near == 0.01);
    EXPECT_OK(MODEL "observer:\n"
                    "  id: 18446744073709551615\n"
                    "  reference_id: 0\n"
                    "  normal_from:\n"
                    "    types: [2, 3]\n"
                    "    radius: 12.5\n"
                    "    sign: +1\n"
                    "  dim: false\n"
                    "  dim_near: 0.5\n"
                    "camera: {projection: hammer-aitoff}\n",
              NULL, 0);
    CHECK(s->observer.id == UINT64_MAX && s->observer.reference_id == 0);
    CHECK(s->observer.normal_types == ((1u << 2) | (1u << 3)) && !s->observer.has_normal);
    CHECK(s->observer.normal_radius == 12.5 && s->observer.normal_sign == 1 && s->observer.dim == 0 && s->observer.dim_near == 0.5);
    EXPECT_OK(OBSERVER "  normal: [0, 1, 1]\n", NULL, 0);
    CHECK(s->observer.has_normal && s->observer.normal.y == 1 && s->observer.normal.z == 1);
    EXPECT_OK(OBSERVER "  normal_from: {types: 2, sign: -1}\n", NULL, 0);
    CHECK(s->observer.normal_types == 4u && s->observer.normal_sign == -1);
    EXPECT_OK(OBSERVER "  normal_from: {types: 2, sign: 1}\n", NULL, 0);
    CHECK(s->observer.normal_sign == 1);
    /* Ids in exponent form are fine while exact. */
    EXPECT_OK(MODEL "observer: {id: 1e6, reference_id: 2}\n", NULL, 0);
    CHECK(s->observer.id == 1000000);
    /* The camera keys that do not place the camera stay allowed. */
    EXPECT_OK(OBSERVER "camera: {projection: dome, zenith: [0, 90], roll: 5}\n", NULL, 0);
}

static void test_observer_key_errors(void)
{
    EXPECT_ERROR(MODEL "observer:\n  id: -1\n", ORR_ERR_USAGE, "scene.yaml:5: observer.id: -1 is out of range");
    EXPECT_ERROR(MODEL "observer:\n  id: 18446744073709551616\n", ORR_ERR_USAGE,
                 "observer.id: 18446744073709551616 is out of range (0 to 18446744073709551615)");
    EXPECT_ERROR(MODEL "observer:\n  id: sun\n", ORR_ERR_USAGE, "observer.id: expected an integer, got 'sun'");
    EXPECT_ERROR(MODEL "observer:\n  id: [1]\n", ORR_ERR_USAGE, "observer.id: expected a particle id");
    EXPECT_ERROR(OBSERVER "  normal: [0, 0]\n", ORR_ERR_USAGE, "scene.yaml:7: observer.normal: expected a list of 3 numbers");
    EXPECT_ERROR(OBSERVER "  normal_from:\n    sign: 2\n", ORR_ERR_USAGE,
                 "scene.yaml:8: observer.normal_from.sign: expected one of: +1 -1, got '2'");
    EXPECT_ERROR(OBSERVER "  normal_from:\n    radius: 0\n", ORR_ERR_USAGE,
                 "observer.normal_from.radius: 0 is out of range (must be > 0)");
    EXPECT_ERROR(OBSERVER "  normal_from:\n    types: [6]\n", ORR_ERR_USAGE,
                 "observer.normal_from.types[0]: 6 is out of range (0 to 5)");
    EXPECT_ERROR(OBSERVER "  dim: sometimes\n", ORR_ERR_USAGE, "observer.dim: expected true or false");
    EXPECT_ERROR(OBSERVER "  dim_near: -0.1\n", ORR_ERR_USAGE, "observer.dim_near: -0.1 is out of range (must be > 0)");
    EXPECT_ERROR(OBSERVER "  normal_form:\n    types: 2\n", ORR_ERR_USAGE,
                 "scene.yaml:7: unknown key 'observer.normal_form' (did you mean 'observer.normal_from'?)");
}

static void test_observer_checks(void)
{
    EXPECT_ERROR(MODEL "observer:\n  id: 7\n", ORR_ERR_USAGE, "scene.yaml:5: observer.id needs observer.reference_id");
    EXPECT_ERROR(MODEL "observer:\n  reference_id: 7\n", ORR_ERR_USAGE,
                 "scene.yaml:5: observer.reference_id is set but observer.id is not");
    EXPECT_ERROR(MODEL "observer:\n  dim: false\n", ORR_ERR_USAGE,
                 "scene.yaml:5: observer.dim applies to an observer-centred sky, but observer.id is not set");
    EXPECT_ERROR(MODEL "observer:\n  id: 7\n  reference_id: 7\n", ORR_ERR_USAGE,
                 "scene.yaml:6: observer.reference_id equals observer.id (7)");
    static const char *const placement[] = {"position: [0, 0, 1]", "look_at: [1, 0, 0]", "direction: [1, 0, 0]",
                                            "quaternion: [1, 0, 0, 0]"};
    for (int i = 0; i < 4; i++) {
        char yaml[256], want[256];
        snprintf(yaml, sizeof yaml, OBSERVER "camera:\n  %s\n", placement[i]);
        snprintf(want, sizeof want, "scene.yaml:8: camera.%.*s is not allowed with observer.id: the observer particle "
                 "places and orients the camera", (int)strcspn(placement[i], ":"), placement[i]);
        EXPECT_ERROR(yaml, ORR_ERR_USAGE, want);
    }
    EXPECT_ERROR(OBSERVER "  normal: [0, 0, 1]\n  normal_from:\n    types: [2]\n", ORR_ERR_USAGE,
                 "scene.yaml:9: observer.normal and observer.normal_from.types are both set");
    EXPECT_ERROR(OBSERVER "  normal: [0, 0, 1]\n  normal_from: {radius: 5}\n", ORR_ERR_USAGE,
                 "observer.normal and observer.normal_from.radius are both set");
    EXPECT_ERROR(OBSERVER "  normal_from: {radius: 5}\n", ORR_ERR_USAGE,
                 "scene.yaml:7: observer.normal_from.radius needs observer.normal_from.types");
    EXPECT_ERROR(OBSERVER "  normal: [0, 0, 0]\n", ORR_ERR_USAGE, "scene.yaml:7: observer.normal: must not be [0, 0, 0]");
    /* The checks see the overrides and name them. */
    const char *same[] = {"observer.reference_id=7"};
    EXPECT_ERROR_SETS(OBSERVER, same, 1, ORR_ERR_USAGE, "--set observer.reference_id=7: observer.reference_id equals");
    const char *pos[] = {"camera.position=[1,2,3]"};
    EXPECT_ERROR_SETS(OBSERVER, pos, 1, ORR_ERR_USAGE, "--set camera.position=[1,2,3]: camera.position is not allowed");
    const char *add[] = {"observer.id=3", "observer.reference_id=4"};
    EXPECT_OK(MODEL, add, 2);
    CHECK(g_scene.observer.has_id && g_scene.observer.id == 3 && g_scene.observer.reference_id == 4);
}

/* The units written into FITS: the model's own by default, what the scene
 * says otherwise; keys that are no FITS unit are refused by name. */
static void test_output_units(void)
{
    EXPECT_OK(MODEL, NULL, 0);
    CHECK(strcmp(scene_weight_unit(&g_scene, NULL), "10**10 solMass") == 0);
    CHECK(strcmp(scene_length_unit(&g_scene, NULL), "kpc") == 0);
    const char *sets[] = {"output.bunit=solMass", "output.length_unit=Mpc"};
    EXPECT_OK(MODEL, sets, 2);
    CHECK(strcmp(scene_weight_unit(&g_scene, NULL), "solMass") == 0);
    CHECK(strcmp(scene_length_unit(&g_scene, NULL), "Mpc") == 0);
    /* The scene's keys win over a file's units. */
    CHECK(strcmp(scene_weight_unit(&g_scene, "g"), "solMass") == 0);
    CHECK(strcmp(scene_length_unit(&g_scene, "pc"), "Mpc") == 0);
    EXPECT_ERROR(MODEL "output:\n  bunit: mass/sr\n", ORR_ERR_USAGE, "scene.yaml:5: output.bunit: 'mass/sr' divides");
    EXPECT_ERROR(MODEL "output:\n  bunit: 'a,b'\n", ORR_ERR_USAGE, "output.bunit: 'a,b' is not a FITS unit string");
    EXPECT_ERROR(MODEL "output:\n  length_unit: kpc2\n", ORR_ERR_USAGE,
                 "scene.yaml:5: output.length_unit: 'kpc2' is not a single FITS unit symbol");
}

int main(void)
{
    RUN(test_defaults);
    RUN(test_full_scene);
    RUN(test_camera_orientations);
    RUN(test_file_paths);
    RUN(test_missing_file);
    RUN(test_load_string_names);
    RUN(test_overrides);
    RUN(test_bad_overrides);
    RUN(test_yaml_errors);
    RUN(test_key_errors);
    RUN(test_value_errors);
    RUN(test_cross_checks);
    RUN(test_sky_defaults);
    RUN(test_sky_keys);
    RUN(test_sky_key_errors);
    RUN(test_zenith_front);
    RUN(test_observer_keys);
    RUN(test_observer_key_errors);
    RUN(test_observer_checks);
    RUN(test_output_units);
    return check_summary();
}
