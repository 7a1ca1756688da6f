/* See thick_disc.h. */
#include "thick_disc.h"

#include <stdint.h>

void thick_disc(size_t n, float *x, float *y, float *z)
{
    uint64_t s = 12345;
    for (size_t i = 0; i < n; i++) {
        float u[3];
        for (int k = 0; k < 3; k++) {
            s = s * 6364136223846793005ULL + 1442695040888963407ULL;
            u[k] = (float)((s >> 11) * (1.0 / 9007199254740992.0));
        }
        x[i] = 30.0f * (u[0] - 0.5f);
        y[i] = 30.0f * (u[1] - 0.5f);
        z[i] = 2.0f * (u[2] - 0.5f);
    }
}
