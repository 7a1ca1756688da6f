/* core/radix.h: the radix sort against qsort by (key, index), on keys
 * whose varying bits lie low, high, or across all 64 (so passes are
 * skipped, taken, or both), with many duplicate keys (stability), and on
 * none and one item. */
#include <stdint.h>
#include <stdlib.h>

#include "check.h"
#include "core/radix.h"

static uint64_t next(uint64_t *state)
{
    *state ^= *state << 13;
    *state ^= *state >> 7;
    *state ^= *state << 17;
    return *state;
}

static int by_key_then_index(const void *pa, const void *pb)
{
    const orr_radix_item *a = pa, *b = pb;
    if (a->key != b->key)
        return a->key < b->key ? -1 : 1;
    return (a->index > b->index) - (a->index < b->index);
}

/* n items with keys (random & mask) | fixed, made in index order. */
static void check_sort(size_t n, uint64_t mask, uint64_t fixed, uint64_t seed)
{
    orr_radix_item *items = malloc((n ? 2 * n : 2) * sizeof *items), *want = malloc((n ? n : 1) * sizeof *want);
    for (size_t i = 0; i < n; i++) {
        items[i] = (orr_radix_item){(next(&seed) & mask) | fixed, i};
        want[i] = items[i];
    }
    qsort(want, n, sizeof *want, by_key_then_index);
    const orr_radix_item *got = orr_radix_sort(items, items + n, n);
    size_t differ = 0;
    for (size_t i = 0; i < n; i++)
        differ += got[i].key != want[i].key || got[i].index != want[i].index;
    if (differ)
        fprintf(stderr, "  %zu items, mask %llx: %zu differ from qsort\n", n, (unsigned long long)mask, differ);
    CHECK(differ == 0);
    free(items);
    free(want);
}

static void test_against_qsort(void)
{
    check_sort(0, ~0ull, 0, 1);
    check_sort(1, ~0ull, 0, 2);
    check_sort(100000, 0xfffull, 0, 3);                      /* 4096 keys: many equal, one or two passes */
    check_sort(100000, 0x7ffffffull, 0, 4);                   /* the dust's 27-bit direction keys */
    check_sort(100000, 0xffffull << 40, 0x5a5a, 5);           /* only high bits vary: the low passes skipped */
    check_sort(100000, ~0ull, 0, 6);                          /* all 64 bits */
    check_sort(50000, 0x3ull | 0x3ull << 62, 1ull << 33, 7); /* a few keys at both ends */
}

/* Every key the same: no pass at all, the items untouched in order. */
static void test_all_equal(void)
{
    orr_radix_item items[2 * 5];
    for (size_t i = 0; i < 5; i++)
        items[i] = (orr_radix_item){42, 4 - i};
    const orr_radix_item *got = orr_radix_sort(items, items + 5, 5);
    CHECK(got == items);
    for (size_t i = 0; i < 5; i++)
        CHECK(got[i].key == 42 && got[i].index == 4 - i);
}

int main(void)
{
    RUN(test_against_qsort);
    RUN(test_all_equal);
    return check_summary();
}
