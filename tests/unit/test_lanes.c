/* How many lanes a view splats in (reduce/lanes.h): a function of the
 * image and the particle count alone, within the memory budget, with a
 * second lane for images too large for the budget but not for
 * ORR_LANE_SECOND_MAX. */
#include "check.h"
#include "reduce/lanes.h"

static void test_kernels_by_size(void)
{
    CHECK(orr_lanes_for(1024, 1024, 1, 0, -1) == ORR_MAX_LANES);
    CHECK(orr_lanes_for(3600, 3600, 3, 0, -1) == 2); /* 155 MB a copy: one within 256 MB */
    CHECK(orr_lanes_for(8192, 8192, 3, 0, -1) == 2); /* 805 MB: the second lane past the budget */
    CHECK(orr_lanes_for(16384, 16384, 1, 0, -1) == 2); /* exactly 1 GiB */
    CHECK(orr_lanes_for(8192, 8192, 5, 0, -1) == 1); /* 1.34 GB: one thread */
    CHECK(orr_lanes_for(16384, 16384, 3, 0, -1) == 1);
}

static void test_points_by_count(void)
{
    /* Point deposits: a lane for every ORR_LANE_SHARES_PER_PIXEL shares a
     * pixel, whatever the size allows. */
    CHECK(orr_lanes_for(1024, 1024, 1, 1, 1000) == 1);
    CHECK(orr_lanes_for(1024, 1024, 1, 1, 3 * 4 * 1024 * 1024) == 3);
    CHECK(orr_lanes_for(8192, 8192, 3, 4, 10000000) == 1);
    CHECK(orr_lanes_for(1024, 1024, 1, 4, -1) == ORR_MAX_LANES); /* count unknown */
}

int main(void)
{
    RUN(test_kernels_by_size);
    RUN(test_points_by_count);
    return check_summary();
}
