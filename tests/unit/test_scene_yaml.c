/* The scene as YAML (yt_yaml_text), which FITS files store as their SCENE
 * extension: whatever the parser read, the text reads back as the same tree
 * (keys, scalars' text, null or not, lists, nested mappings), so a render of
 * it binds the same scene. */
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "scene/scene.h"
#include "scene/ytree.h"

/* Whether two trees hold the same keys and values: the same text, and a
 * null where the other has one (a quoted "~" is text, a plain one null). */
static int same_tree(const yt_node *a, const yt_node *b)
{
    if (a->kind != b->kind || a->n != b->n)
        return 0;
    if (a->kind == YT_SCALAR) {
        int a_null = !a->quoted && yt_is_null(a), b_null = !b->quoted && yt_is_null(b);
        return a_null == b_null && (a_null || strcmp(a->text, b->text) == 0);
    }
    for (size_t i = 0; i < a->n; i++) {
        if (a->kind == YT_SEQUENCE && !same_tree(a->items[i], b->items[i]))
            return 0;
        if (a->kind == YT_MAPPING && (strcmp(a->entries[i].key, b->entries[i].key) != 0 ||
                                      !same_tree(a->entries[i].value, b->entries[i].value)))
            return 0;
    }
    return 1;
}

/* text -> tree -> YAML -> tree: the same tree, and the YAML a fixed point. */
static void round_trip(const char *text)
{
    orr_error err = {0};
    yt_node *first = NULL, *second = NULL;
    CHECK(yt_parse(text, strlen(text), "test", 1, &first, &err) == ORR_OK && first);
    char *yaml = first ? yt_yaml_text(first, &err) : NULL;
    CHECK(yaml != NULL);
    if (!yaml) {
        yt_free(first);
        return;
    }
    orr_status st = yt_parse(yaml, strlen(yaml), "again", 1, &second, &err);
    CHECK(st == ORR_OK && second);
    if (st != ORR_OK)
        fprintf(stderr, "  %s\n  in:\n%s", err.msg, yaml);
    if (second) {
        int same = same_tree(first, second);
        CHECK(same);
        if (!same)
            fprintf(stderr, "  from:\n%s\n  as YAML:\n%s", text, yaml);
        char *yaml2 = yt_yaml_text(second, &err);
        CHECK(yaml2 && strcmp(yaml, yaml2) == 0);
        free(yaml2);
    }
    free(yaml);
    yt_free(first);
    yt_free(second);
}

static void test_plain_and_nested(void)
{
    round_trip("input:\n  model:\n    name: mw-m31\n    particles: 2000\n  types: [2, 3]\n"
               "camera:\n  position: [-32, 46.5, 0]\n  fov: 1e-3\n  roll: -.5\nimage: {width: 64}\n");
}

static void test_strings_that_need_quotes(void)
{
    round_trip("output:\n  bunit: 10**10 solMass\n  name: 'a: b # c'\n  dir: \"with \\\"quotes\\\" and \\\\\"\n"
               "  sep: '-'\n  dots: '...'\n  flow: '[x, y]'\n  star: '*x'\n  amp: '&x'\n  sharp: '#x'\n"
               "  utf8: \"\xc3\xa9toile\"\n  tab: \"a\\tb\"\n  newline: \"a\\nb\"\n  spaces: ' a '\n");
}

static void test_nulls_and_quoted_nulls(void)
{
    round_trip("camera:\ndome:\n  profile: ~\n  tilt: null\noutput:\n  name: '~'\n  dir: 'null'\n"
               "  image: ''\nviews: {}\nlist: [a, ~, '']\n");
}

static void test_lists_of_mappings_and_odd_keys(void)
{
    round_trip("colour:\n  populations:\n    - name: disc stars\n      select: {types: [2, 3]}\n"
               "      colour: {temperature: 5000}\n    - {name: 'b, c', luminance: {mass: 1}}\n"
               "'odd key': 1\n'': 2\n'-x': [[1, 2], [3]]\n"
               "block:\n  - a, b\n  - key: x]y {z}\n    other: x - q\n  - - nested\n");
}

/* A scene's scene_yaml: a comment naming the folder of its relative file
 * names, then YAML that loads as the same scene (overrides included). */
static orr_scene g_scene, g_again;

static void test_scene_keeps_overrides(void)
{
    orr_error err = {0};
    const char *text = "input:\n  model:\n    name: mw-m31\n    particles: 1000\nimage:\n  width: 32\n";
    const char *sets[] = {"image.height=24", "output.bunit=10**10 solMass"};
    orr_scene_free(&g_scene);
    CHECK(orr_scene_load_string(&g_scene, text, "s.yaml", "/tmp", sets, 2, &err) == ORR_OK);
    CHECK_CONTAINS(g_scene.scene_yaml, "# are relative to /tmp\n");
    CHECK_CONTAINS(g_scene.scene_yaml, "  height: 24\n");
    CHECK_CONTAINS(g_scene.scene_yaml, "  bunit: \"10**10 solMass\"\n");
    orr_scene_free(&g_again);
    CHECK(orr_scene_load_string(&g_again, g_scene.scene_yaml, "s.yaml", "/tmp", NULL, 0, &err) == ORR_OK);
    CHECK(g_again.projection.width == 32 && g_again.projection.height == 24);
    CHECK(strcmp(g_again.output.bunit, "10**10 solMass") == 0);
    CHECK(g_again.settings_digest == g_scene.settings_digest);
}

int main(void)
{
    RUN(test_plain_and_nested);
    RUN(test_strings_that_need_quotes);
    RUN(test_nulls_and_quoted_nulls);
    RUN(test_lists_of_mappings_and_odd_keys);
    RUN(test_scene_keeps_overrides);
    return check_summary();
}
