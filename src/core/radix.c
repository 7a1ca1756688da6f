#include "core/radix.h"

#include <string.h>

#define RADIX_BITS 11
#define RADIX_SIZE (1u << RADIX_BITS)

/* 11 bits a pass: 2048 counters stay in the first-level cache. Digits that
 * are the same in every key (the high bits of ids below 2^32, say) take no
 * pass. */
orr_radix_item *orr_radix_sort(orr_radix_item *items, orr_radix_item *tmp, size_t n)
{
    uint64_t any = 0, every = ~(uint64_t)0;
    for (size_t i = 0; i < n; i++) {
        any |= items[i].key;
        every &= items[i].key;
    }
    const uint64_t varying = any ^ every;
    size_t count[RADIX_SIZE];
    for (unsigned shift = 0; shift < 64; shift += RADIX_BITS) {
        if (((varying >> shift) & (RADIX_SIZE - 1)) == 0)
            continue;
        memset(count, 0, sizeof count);
        for (size_t i = 0; i < n; i++)
            count[(items[i].key >> shift) & (RADIX_SIZE - 1)]++;
        size_t sum = 0;
        for (size_t d = 0; d < RADIX_SIZE; d++) {
            const size_t c = count[d];
            count[d] = sum;
            sum += c;
        }
        for (size_t i = 0; i < n; i++)
            tmp[count[(items[i].key >> shift) & (RADIX_SIZE - 1)]++] = items[i];
        orr_radix_item *swap = items;
        items = tmp;
        tmp = swap;
    }
    return items;
}
