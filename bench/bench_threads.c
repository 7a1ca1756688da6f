/* The renderer's splat (orr_render_frame: gather, project, deposit in
 * lanes, the lanes' reduction) timed on N particles held in memory, so that
 * no reader or model generator is timed with it. Threads come from
 * OMP_NUM_THREADS (or the machine's cores).
 *
 *   OMP_NUM_THREADS=2 bench_threads [N [repeats [CASE]]]     default: 4e6, 3, all
 *
 * Cases: NGP orthographic 1024^2, NGP and CIC dome master 3600^2 (from
 * inside the particles), SPH orthographic 1024^2 (h about 1.7 pixels; N / 4
 * particles, the kernel costing more). Prints, per case, the best of the
 * repeats: seconds from the start of the frame to the end of the splat
 * (the last progress call: set-up, splat and lanes included, FITS output
 * excluded), particles per second, and the CPU seconds of that repeat.
 * CASE (a word of a case's name: ngp, dome, sph) runs that case alone. */
#include <omp.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "frame_timer.h"
#include "thick_disc.h"

int main(int argc, char **argv)
{
    size_t n = argc > 1 ? (size_t)atof(argv[1]) : 4000000;
    int repeats = argc > 2 ? atoi(argv[2]) : 3;
    const char *only = argc > 3 ? argv[3] : NULL;
    float *x = malloc(n * sizeof *x), *y = malloc(n * sizeof *y), *z = malloc(n * sizeof *z);
    float *h = malloc(n * sizeof *h);
    if (!x || !y || !z || !h || n == 0 || repeats < 1) {
        fprintf(stderr, "usage: bench_threads [N [repeats]]\n");
        return 1;
    }
    thick_disc(n, x, y, z);
    for (size_t i = 0; i < n; i++)
        h[i] = 0.05f;
    orr_particle_arrays a = {.n = n, .x = {x, ORR_F32, 0}, .y = {y, ORR_F32, 0}, .z = {z, ORR_F32, 0},
                             .mass_value = 1.0, .h = {h, ORR_F32, 0}};
    orr_particle_arrays quarter = a;
    quarter.n = n / 4;
    static const struct {
        const char *name;
        const char *yaml;
        int quarter;
    } cases[] = {
        {"ngp orthographic 1024^2",
         "input: {insitu: true}\ncamera: {projection: orthographic, width: 30}\nimage: {width: 1024, height: 1024}\n"
         "deposit: ngp\noutput: {name: bench_threads, fits: false}\n",
         0},
        {"ngp dome 3600^2",
         "input: {insitu: true}\ncamera: {projection: dome, position: [0.5, 0.5, 0]}\nimage: {width: 3600, height: 3600}\n"
         "deposit: ngp\noutput: {name: bench_threads, fits: false}\n",
         0},
        {"cic dome 3600^2",
         "input: {insitu: true}\ncamera: {projection: dome, position: [0.5, 0.5, 0]}\nimage: {width: 3600, height: 3600}\n"
         "deposit: cic\noutput: {name: bench_threads, fits: false}\n",
         0},
        {"sph orthographic 1024^2",
         "input: {insitu: true}\ncamera: {projection: orthographic, width: 30}\nimage: {width: 1024, height: 1024}\n"
         "deposit: sph\nsmoothing: {lengths: file}\noutput: {name: bench_threads, fits: false}\n",
         1},
    };
    printf("threads %d, best of %d\n", omp_get_max_threads(), repeats);
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        if (only && !strstr(cases[k].name, only))
            continue;
        const orr_particle_arrays *p = cases[k].quarter ? &quarter : &a;
        double cpu = 0, t = frame_timer_best(cases[k].yaml, p, repeats, &cpu);
        printf("%-26s N %9zu  %7.3f s  %6.2f M particles/s  (CPU %.3f s)\n", cases[k].name, p->n, t,
               p->n / t / 1e6, cpu);
        fflush(stdout);
    }
    free(x), free(y), free(z), free(h);
    return 0;
}
