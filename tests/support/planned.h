/* Projections for tests: made the one way there is (orr_projection_plan),
 * from settings checked (orr_projection_check) that the test knows to be
 * good. */
#ifndef ORR_TEST_PLANNED_H
#define ORR_TEST_PLANNED_H

#include "frame/projection.h"

/* The projection planned from settings, checked; a refusal is a broken
 * test, so it prints the message and exits. */
orr_projection test_projection_planned(orr_projection_settings settings);

/* The same from designated initialisers, as a literal reads:
 * PLANNED(.kind = ORR_PROJ_DOME, .width = 101, .height = 101, .dome_fov_deg = 180). */
#define PLANNED(...) test_projection_planned((orr_projection_settings){__VA_ARGS__})

#endif
