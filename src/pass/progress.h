/* How the splat pass tells its caller how far it is (orrery render's
 * progress line, the in-situ API's). */
#ifndef ORR_PASS_PROGRESS_H
#define ORR_PASS_PROGRESS_H

#include <stdint.h>

/* Called after each chunk with the particles read so far and the total
 * (-1 when the source does not know it). */
typedef void (*orr_progress_fn)(void *user, uint64_t done, int64_t total);

#endif
