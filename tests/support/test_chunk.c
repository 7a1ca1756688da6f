#include "test_chunk.h"

#include <stdio.h>
#include <stdlib.h>

orr_chunk test_chunk(size_t n, const char *const *extra, int nextra)
{
    orr_chunk c;
    orr_error err;
    if (orr_chunk_alloc(&c, n, 0, extra, nextra, &err) != ORR_OK) {
        fprintf(stderr, "cannot allocate a chunk: %s\n", err.msg);
        exit(1);
    }
    c.n = n;
    for (size_t i = 0; i < n; i++) {
        c.x[i] = c.y[i] = c.z[i] = 0;
        c.mass[i] = 1;
        c.id[i] = i + 1;
        c.type[i] = 0;
        for (int k = 0; k < nextra; k++)
            c.extra[k].data[i] = 0;
    }
    return c;
}
