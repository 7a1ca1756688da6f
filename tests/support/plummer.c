/* See plummer.h. The enclosed mass fraction of a Plummer sphere is
 * f(r) = r^3 / (1 + r^2)^(3/2), so a uniform f in (0, f(rmax)) gives
 * r = 1 / sqrt(f^(-2/3) - 1); the direction is uniform on the sphere
 * (cos theta uniform in (-1, 1)). */
#include "plummer.h"

#include <math.h>

#include "source/models/rng.h"

void plummer_positions(size_t n, uint64_t seed, double rmax, float *x, float *y, float *z)
{
    double fmax = rmax * rmax * rmax / pow(1.0 + rmax * rmax, 1.5);
    for (size_t i = 0; i < n; i++) {
        orr_rng rng = orr_rng_seed(seed, i, 0);
        double f = fmax * orr_rng_uniform(&rng);
        double r = 1.0 / sqrt(pow(f, -2.0 / 3.0) - 1.0);
        double cz = 2.0 * orr_rng_uniform(&rng) - 1.0;
        double phi = 6.283185307179586 * orr_rng_uniform(&rng);
        double s = sqrt(1.0 - cz * cz);
        x[i] = (float)(r * s * cos(phi));
        y[i] = (float)(r * s * sin(phi));
        z[i] = (float)(r * cz);
    }
}
