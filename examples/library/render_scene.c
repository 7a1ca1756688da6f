/* A program that links liborrery: loads a scene file, applies overrides given
 * on the command line, renders it and prints where the outputs went.
 *
 *   cc render_scene.c $(pkg-config --cflags --libs orrery) -o render_scene
 *   ./render_scene scene.yaml image.width=512
 */
#include <stdio.h>

#include <render/render.h>
#include <scene/scene.h>

int main(int argc, char **argv)
{
    if (argc < 2) {
        fprintf(stderr, "usage: %s SCENE.yaml [KEY=VALUE ...]\n", argv[0]);
        return 2;
    }
    static orr_scene scene; /* large (paths): keep it off the stack */
    static orr_render_report report;
    orr_error err = {0};
    if (orr_scene_load(&scene, argv[1], (const char *const *)argv + 2, argc - 2, &err) ||
        orr_render_scene(&scene, &report, NULL, NULL, &err)) {
        fprintf(stderr, "render_scene: %s\n", err.msg);
        return 1;
    }
    printf("%llu particles, weight in the image %.9g\n", (unsigned long long)report.n_read,
           report.deposit.deposited);
    for (int i = 0; i < report.noutputs; i++)
        printf("wrote %s\n", report.outputs[i]);
    return 0;
}
