/* Fuzz target for the scene loader: YAML scene text and --set overrides
 * through orr_scene_load_views_string, which parses, applies the overrides,
 * merges the views, binds every key, checks the keys against each other and
 * binds the dome profile named by camera.dome (read from the project's
 * domes/ folder: the scene's base folder is configs/, so <base>/../domes is
 * searched; $ORRERY_DOMES is cleared so the environment does not matter).
 *
 * The input: the scene's YAML text, then zero or more overrides, each after
 * a NUL byte (a NUL cannot be in a scene file: scene_read_text refuses it):
 *
 *     <yaml> [ \0 <key=value> ]...
 *
 * e.g. "image:\n  width: 64\n\0camera.fov=30\0views.a.image.width=8". An
 * empty piece (two NULs in a row, or a trailing NUL) is an empty override,
 * which must be refused, not skipped. At most FUZZ_SCENE_MAX_OVERRIDES are
 * passed; the rest of the input is ignored.
 *
 * The YAML part is then also bound as a dome profile on its own (the
 * profiles in domes/ are seeds too). Nothing is written or rendered. After a successful load the cheap,
 * side-effect-free queries the renderer makes of a scene are made of every
 * view too (its static camera, look target and sequence files). Errors are
 * fine; a crash, sanitizer report, hang or leak is a bug, and so is a
 * success that hands back no views or more than ORR_SCENE_MAX_VIEWS.
 * FUZZ_SCENE_VERBOSE=1 in the environment prints each input's outcome. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "scene/scene.h"
#include "scene/scene_bind.h"
#include "scene/ytree.h"

#ifndef ORRERY_FUZZ_SCENE_DIR
#define ORRERY_FUZZ_SCENE_DIR "."
#endif

#define FUZZ_SCENE_MAX_OVERRIDES 16

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

/* The YAML part is also bound as a dome profile (domes/NAME.yaml), as
 * scene_dome.c binds a profile file: the seeds from domes/ exercise this. */
static void bind_as_dome_profile(const char *text)
{
    yt_node *root = NULL;
    orr_error err = {0};
    if (yt_parse(text, strlen(text), "fuzz-dome.yaml", 1, &root, &err) == ORR_OK && root &&
        root->kind == YT_MAPPING) {
        dome_profile p;
        memset(&p, 0, sizeof p);
        if (dome_profile_bind(&p, root, &err) == ORR_OK &&
            (memchr(p.description, '\0', sizeof p.description) == NULL || (p.has_size && p.size < 1)))
            abort();
    }
    yt_free(root);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static int initialised, verbose;
    if (!initialised) {
        verbose = getenv("FUZZ_SCENE_VERBOSE") != NULL;
        unsetenv("ORRERY_DOMES");
        initialised = 1;
    }
    /* One copy with a NUL after every piece. */
    char *text = malloc(size + 1);
    if (!text)
        abort();
    if (size)
        memcpy(text, data, size);
    text[size] = '\0';
    const char *overrides[FUZZ_SCENE_MAX_OVERRIDES];
    int n = 0;
    size_t yaml_len = strlen(text);
    for (size_t at = yaml_len; at < size && n < FUZZ_SCENE_MAX_OVERRIDES;) {
        const char *piece = text + at + 1; /* after the NUL at text[at] */
        overrides[n++] = piece;
        at += 1 + strlen(piece);
    }
    orr_scene_views *views = malloc(sizeof *views);
    if (!views)
        abort();
    orr_error err = {0};
    orr_status st = orr_scene_load_views_string(views, text, "fuzz.yaml", ORRERY_FUZZ_SCENE_DIR,
                                                n ? overrides : NULL, n, &err);
    if (verbose)
        fprintf(stderr, "fuzz_scene: %d override(s): %s\n", n, st == ORR_OK ? "loaded" : err.msg);
    if (st == ORR_OK) {
        if (views->n < 1 || views->n > ORR_SCENE_MAX_VIEWS)
            abort();
        for (int v = 0; v < views->n; v++) {
            const orr_scene *s = &views->view[v];
            orr_camera cam;
            orr_vec3 target;
            orr_error cam_err = {0};
            (void)orr_scene_static_camera(s, &cam, &cam_err);
            (void)orr_scene_look_target(s, &target);
            /* The owned strings' convention (core/owned.h): a loaded scene
             * always has its path, folder and output folder; a string set
             * is never "". */
            const char *const owned[] = {s->input.file, s->input.sequence.pattern, s->camera.path_file,
                                         s->dust.curve_file, s->psf.file};
            if (!s->path || !s->dir || !s->output.dir || !s->path[0] || !s->dir[0] || !s->output.dir[0])
                abort();
            for (size_t i = 0; i < sizeof owned / sizeof owned[0]; i++)
                if (owned[i] && !owned[i][0])
                    abort();
            const char *end = s->input.sequence.files + sizeof s->input.sequence.files;
            for (int i = 0; i < s->input.sequence.nfiles; i++) {
                const char *p = orr_scene_sequence_file(s, i);
                if (!p || p < s->input.sequence.files || p >= end || !memchr(p, '\0', (size_t)(end - p)))
                    abort(); /* a path outside the scene's own buffer */
            }
        }
    } else if (err.msg[0] == '\0') {
        abort(); /* an error must say what was wrong */
    }
    orr_scene_views_free(views); /* a failed load has freed its own */
    free(views);
    bind_as_dome_profile(text);
    free(text);
    return 0;
}
