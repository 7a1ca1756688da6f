/* Sorting keys with the indices of what they stand for: a least-significant-
 * digit radix sort, for the millions of keys of a snapshot's ids and of a
 * chunk's stars grouped by direction, several times faster than qsort. */
#ifndef ORR_CORE_RADIX_H
#define ORR_CORE_RADIX_H

#include <stddef.h>
#include <stdint.h>

typedef struct orr_radix_item {
    uint64_t key;
    size_t index;
} orr_radix_item;

/* Sorts items[0, n) by key, stably: items with equal keys keep their order
 * (so items made in index order end sorted by key, then index). tmp holds n
 * items. Returns the array that holds the result, items or tmp. */
orr_radix_item *orr_radix_sort(orr_radix_item *items, orr_radix_item *tmp, size_t n);

#endif
