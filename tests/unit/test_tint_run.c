/* colour.tint.t: run: the scene key takes a number or the word run, a
 * --set of either replaces the other, and the tinted-map keys of
 * colour.synthesis are accepted with a tint. (The renderer's use of it,
 * blue at frame 0 and red at the last, is tests/cli/test_dark_universe.sh.) */
#include <stdio.h>
#include <string.h>

#include "check.h"
#include "scene/scene.h"

static orr_scene g_scene; /* large: keep it off the stack */

#define TINT "input:\n  model: {name: mw-m31}\ncolour:\n  tint:\n    path: [20000, 2500]\n"

static orr_status load(const char *yaml, const char *set, orr_error *err)
{
    orr_error_clear(err);
    const char *sets[1] = {set};
    orr_scene_free(&g_scene);
    return orr_scene_load_string(&g_scene, yaml, "scene.yaml", ".", set ? sets : NULL, set ? 1 : 0, err);
}

static void test_run_word(void)
{
    orr_error err;
    CHECK(load(TINT "    t: run\n", NULL, &err) == ORR_OK);
    CHECK(g_scene.colour.tint_run == 1);
    CHECK(load(TINT "    t: 0.25\n", NULL, &err) == ORR_OK);
    CHECK(g_scene.colour.tint_run == 0);
    CHECK_NEAR(g_scene.colour.tint_t, 0.25, 0);
    CHECK(load(TINT, NULL, &err) == ORR_OK); /* default: fixed at 0 */
    CHECK(g_scene.colour.tint_run == 0 && g_scene.colour.tint_t == 0);
}

static void test_overrides(void)
{
    orr_error err;
    CHECK(load(TINT "    t: run\n", "colour.tint.t=0.5", &err) == ORR_OK);
    CHECK(g_scene.colour.tint_run == 0);
    CHECK_NEAR(g_scene.colour.tint_t, 0.5, 0);
    CHECK(load(TINT "    t: 0.5\n", "colour.tint.t=run", &err) == ORR_OK);
    CHECK(g_scene.colour.tint_run == 1);
}

static void test_bad_values(void)
{
    orr_error err;
    CHECK(load(TINT "    t: running\n", NULL, &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "scene.yaml:6");
    CHECK_CONTAINS(err.msg, "colour.tint.t: expected a number or run");
    CHECK(load(TINT "    t: [run]\n", NULL, &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "colour.tint.t");
    CHECK(load(TINT "    t: 2\n", NULL, &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "colour.tint.t");
    /* run without a path is as wrong as a number without one */
    CHECK(load("input:\n  model: {name: mw-m31}\ncolour:\n  tint:\n    t: run\n", NULL, &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "colour.tint.t needs colour.tint.path");
}

static void test_synthesis_keys_with_tint(void)
{
    orr_error err;
    CHECK(load(TINT "  synthesis:\n    stretch: gamma\n    white: 3\n", NULL, &err) == ORR_OK);
    CHECK(g_scene.colour.synth.y0 == 3);
    /* without a tint or populations they still apply to nothing */
    CHECK(load("input:\n  model: {name: mw-m31}\ncolour:\n  synthesis:\n    stretch: gamma\n", NULL, &err) ==
          ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "colour.synthesis.stretch applies to colour.populations or colour.tint");
}

int main(void)
{
    RUN(test_run_word);
    RUN(test_overrides);
    RUN(test_bad_values);
    RUN(test_synthesis_keys_with_tint);
    return check_summary();
}
