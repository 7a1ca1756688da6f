/* How many lanes a view splats in (reduce/lanes.h): a function of the
 * image and the particle count alone, within the memory budget, with a
 * second lane for images too large for the budget but not for
 * ORR_LANE_SECOND_MAX, and always a power of two (three lanes would leave
 * one of two threads two of them). */
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
    /* 101 MB a copy: two would fit the budget, but three lanes are two */
    CHECK(orr_lanes_for(4096, 2048, 3, 0, -1) == 2);
    CHECK(orr_lanes_for(3840, 2160, 3, 0, -1) == 2);
    CHECK(orr_lanes_for(4096, 2048, 1, 0, -1) == ORR_MAX_LANES); /* 34 MB: three copies fit */
}

static void test_points_by_count(void)
{
    /* Point deposits: a lane for every ORR_LANE_SHARES_PER_PIXEL shares a
     * pixel, whatever the size allows. */
    CHECK(orr_lanes_for(1024, 1024, 1, 1, 1000) == 1);
    CHECK(orr_lanes_for(1024, 1024, 1, 1, 2 * 4 * 1024 * 1024) == 2);
    CHECK(orr_lanes_for(1024, 1024, 1, 1, 3 * 4 * 1024 * 1024) == 2); /* three: two */
    CHECK(orr_lanes_for(1024, 1024, 1, 1, 4 * 4 * 1024 * 1024) == 4);
    CHECK(orr_lanes_for(8192, 8192, 3, 4, 10000000) == 1);
    CHECK(orr_lanes_for(1024, 1024, 1, 4, -1) == ORR_MAX_LANES); /* count unknown */
}

int main(void)
{
    RUN(test_kernels_by_size);
    RUN(test_points_by_count);
    return check_summary();
}
