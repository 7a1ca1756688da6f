/* The N-body tests' galaxy-like mix of particles (test_nbody_qtree,
 * test_nbody_fmm): a flattened exponential disc (Plummer softening 0.05) in
 * a rounder, heavier halo of particles 8 times as massive (softening 0.1),
 * half of each, the same every time (seeded). */
#ifndef ORR_TEST_GALAXY_MIX_H
#define ORR_TEST_GALAXY_MIX_H

#include <math.h>
#include <stdlib.h>

static void make_galaxy_mix(double *pos, double *mass, double *eps, int n)
{
    srand(5);
    for (int i = 0; i < n; i++) {
        int disc = i < n / 2;
        double u1 = (rand() + 1.0) / (RAND_MAX + 2.0), u2 = (rand() + 1.0) / (RAND_MAX + 2.0);
        double phi = 6.283185307179586 * rand() / RAND_MAX;
        if (disc) {
            double R = -3.0 * log(u1 * u2), z = 0.3 * log(2.0 * rand() / RAND_MAX + 1e-9) * (rand() & 1 ? 1 : -1);
            pos[3 * i] = R * cos(phi);
            pos[3 * i + 1] = R * sin(phi);
            pos[3 * i + 2] = z;
        } else {
            double s = sqrt(u1 * 0.6), r = 30.0 * s / (1.0 - s), c = 2.0 * u2 - 1.0, sn = sqrt(1.0 - c * c);
            pos[3 * i] = r * sn * cos(phi);
            pos[3 * i + 1] = r * sn * sin(phi);
            pos[3 * i + 2] = r * c;
        }
        mass[i] = disc ? 1.0 : 8.0;
        eps[i] = disc ? 0.05 : 0.1;
    }
}

#endif
