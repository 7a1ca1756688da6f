/* A program that links liborrery through its public header only: reads
 * particles (x y z mass, one per line after a header line) from a text
 * file, renders them with a scene's camera and outputs, with overrides from
 * the command line, and prints where the outputs went.
 *
 *   cc render_scene.c $(pkg-config --cflags --libs orrery) -o render_scene
 *   ./render_scene scene.yaml particles.txt image.width=512
 */
#include <orrery/orrery.h>

#include <stdio.h>
#include <stdlib.h>

/* The particles as one packed array of x, y, z, mass per particle. */
static double *read_particles(const char *path, size_t *n)
{
    FILE *f = fopen(path, "r");
    if (!f)
        return NULL;
    char header[256];
    size_t cap = 1024, count = 0;
    double *rows = malloc(cap * 4 * sizeof *rows);
    if (rows && !fgets(header, sizeof header, f))
        count = 0;
    double x, y, z, m;
    while (rows && fscanf(f, "%lf %lf %lf %lf", &x, &y, &z, &m) == 4) {
        if (count == cap) {
            double *more = realloc(rows, 2 * cap * 4 * sizeof *rows);
            if (!more) {
                free(rows);
                rows = NULL;
                break;
            }
            rows = more;
            cap *= 2;
        }
        double *r = rows + 4 * count++;
        r[0] = x, r[1] = y, r[2] = z, r[3] = m;
    }
    fclose(f);
    *n = count;
    return rows;
}

int main(int argc, char **argv)
{
    if (argc < 3) {
        fprintf(stderr, "usage: %s SCENE.yaml PARTICLES.txt [KEY=VALUE ...]\n", argv[0]);
        return 2;
    }
    size_t n = 0;
    double *rows = read_particles(argv[2], &n);
    if (!rows) {
        fprintf(stderr, "render_scene: cannot read %s\n", argv[2]);
        return 1;
    }
    orrery_renderer *r = NULL;
    char msg[1024];
    const size_t stride = 4 * sizeof *rows; /* an array of structures: x, y, z, mass */
    orr_particle_arrays p = {
        .n = n,
        .x = {rows + 0, ORR_F64, stride},
        .y = {rows + 1, ORR_F64, stride},
        .z = {rows + 2, ORR_F64, stride},
        .mass = {rows + 3, ORR_F64, stride},
    };
    int st = orrery_open(&r, argv[1], (const char *const *)argv + 3, argc - 3, msg, sizeof msg);
    if (st != ORRERY_OK)
        fprintf(stderr, "render_scene: %s\n", msg);
    else if ((st = orrery_render(r, &p, 0)) != ORRERY_OK)
        fprintf(stderr, "render_scene: %s\n", orrery_error(r));
    for (int i = 0; st == ORRERY_OK && i < orrery_output_count(r); i++)
        printf("wrote %s\n", orrery_output(r, i));
    if (st == ORRERY_OK)
        printf("%zu particles rendered\n", n);
    orrery_close(r);
    free(rows);
    return st == ORRERY_OK ? 0 : 1;
}
