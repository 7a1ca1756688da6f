#include "core/timings.h"

#include <time.h>

static double seconds_of(clockid_t id)
{
    struct timespec ts;
    if (clock_gettime(id, &ts) != 0)
        return 0.0;
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

orr_clock orr_clock_now(void)
{
    return (orr_clock){seconds_of(CLOCK_MONOTONIC), seconds_of(CLOCK_PROCESS_CPUTIME_ID)};
}

double orr_thread_cpu_seconds(void) { return seconds_of(CLOCK_THREAD_CPUTIME_ID); }

const char *orr_stage_name(orr_stage s)
{
    static const char *const names[ORR_NSTAGES] = {"setup", "source", "lengths", "gather+project", "deposit",
                                                  "reduce", "psf", "colour/post", "fits", "exr", "png",
                                                  "image", "stereo pair", "commit"};
    return s >= 0 && s < ORR_NSTAGES ? names[s] : "?";
}

void orr_stage_charge_split(orr_stage_times *t, orr_stage a, orr_stage b, double share_a, orr_clock *since)
{
    orr_clock now = orr_clock_now();
    if (t) {
        share_a = share_a >= 0.0 && share_a <= 1.0 ? share_a : 1.0; /* NaN (no work measured): all to a */
        double wall = now.wall - since->wall, cpu = now.cpu - since->cpu;
        t->wall[a] += share_a * wall;
        t->cpu[a] += share_a * cpu;
        t->wall[b] += (1.0 - share_a) * wall;
        t->cpu[b] += (1.0 - share_a) * cpu;
    }
    *since = now;
}

void orr_stage_charge(orr_stage_times *t, orr_stage s, orr_clock *since)
{
    orr_stage_charge_split(t, s, s, 1.0, since);
}

void orr_stage_charge_beside(orr_stage_times *t, const orr_stage_times *before, orr_stage s, double cpu)
{
    double own_cpu = t->cpu[s] - before->cpu[s], meanwhile = 0.0;
    for (int k = 0; k < ORR_NSTAGES; k++)
        meanwhile += k == (int)s ? 0.0 : t->cpu[k] - before->cpu[k];
    /* The thread's CPU that the other stages were charged: all of it but
     * what s itself was charged while the caller waited for the thread. */
    double moved = cpu - own_cpu < meanwhile ? cpu - own_cpu : meanwhile;
    moved = moved > 0.0 ? moved : 0.0;
    double share = meanwhile > 0.0 ? moved / meanwhile : 0.0;
    for (int k = 0; k < ORR_NSTAGES; k++) {
        if (k == (int)s)
            continue;
        double dwall = share * (t->wall[k] - before->wall[k]), dcpu = share * (t->cpu[k] - before->cpu[k]);
        t->wall[k] -= dwall, t->cpu[k] -= dcpu;
        t->wall[s] += dwall, t->cpu[s] += dcpu;
    }
}

void orr_stage_times_finish(orr_stage_times *t, orr_clock start)
{
    orr_clock now = orr_clock_now();
    t->total_wall = now.wall - start.wall;
    t->total_cpu = now.cpu - start.cpu;
    t->frames = 1;
}

void orr_stage_times_add(orr_stage_times *to, const orr_stage_times *from)
{
    for (int s = 0; s < ORR_NSTAGES; s++) {
        to->wall[s] += from->wall[s];
        to->cpu[s] += from->cpu[s];
    }
    to->total_wall += from->total_wall;
    to->total_cpu += from->total_cpu;
    to->frames += from->frames;
}

void orr_stage_times_sum(const orr_stage_times *t, double *wall, double *cpu)
{
    *wall = *cpu = 0.0;
    for (int s = 0; s < ORR_NSTAGES; s++) {
        *wall += t->wall[s];
        *cpu += t->cpu[s];
    }
}
