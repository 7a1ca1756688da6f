/* See test_random.h. */
#include "test_random.h"

double test_uniform(uint64_t *state)
{
    *state = *state * 6364136223846793005ULL + 1442695040888963407ULL;
    return (double)(*state >> 11) * (1.0 / 9007199254740992.0);
}

uint64_t test_below(uint64_t *state, uint64_t n)
{
    const uint64_t k = (uint64_t)(test_uniform(state) * (double)n);
    return k < n ? k : n - 1; /* n beyond 2^53: the product may round up to n */
}
