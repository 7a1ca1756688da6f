/* See thick_disc.h. */
#include "thick_disc.h"

#include <stdint.h>

#include "test_random.h"

void thick_disc(size_t n, float *x, float *y, float *z)
{
    uint64_t s = 12345;
    for (size_t i = 0; i < n; i++) {
        float u[3];
        for (int k = 0; k < 3; k++)
            u[k] = (float)test_uniform(&s);
        x[i] = 30.0f * (u[0] - 0.5f);
        y[i] = 30.0f * (u[1] - 0.5f);
        z[i] = 2.0f * (u[2] - 0.5f);
    }
}
