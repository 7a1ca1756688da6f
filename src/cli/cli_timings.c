/* orrery render --timings: where each frame's time went, and a run's total
 * (the numbers are the library's: core/timings.h). */
#include <stdio.h>

#include "cli/cli.h"

/* One line a frame of a run: the totals and the three largest stages. */
static void print_frame_line(long frame, const orr_stage_times *t)
{
    int top[3] = {-1, -1, -1};
    for (int s = 0; s < ORR_NSTAGES; s++)
        for (int k = 0; k < 3; k++)
            if (top[k] < 0 || t->wall[s] > t->wall[top[k]]) {
                for (int m = 2; m > k; m--)
                    top[m] = top[m - 1];
                top[k] = s;
                break;
            }
    printf("timings: frame %ld: %.3f s wall, %.3f s CPU; most in", frame, t->total_wall, t->total_cpu);
    for (int k = 0; k < 3; k++)
        printf("%s %s %.3f s", k ? "," : "", orr_stage_name((orr_stage)top[k]), t->wall[top[k]]);
    printf("\n");
}

void cli_timings_frame(void *user, long frame, const orr_stage_times *t)
{
    cli_timings *ct = user;
    orr_stage_times_add(&ct->total, t);
    if (ct->per_frame_lines)
        print_frame_line(frame, t);
    fflush(stdout);
}

void cli_timings_print(const cli_timings *ct)
{
    const orr_stage_times *t = &ct->total;
    if (t->frames == 0)
        return;
    if (t->frames == 1)
        printf("timings (one frame, every view together):\n");
    else
        printf("timings (the run's %ld frames rendered here, summed; per frame: divide by %ld):\n", t->frames,
               t->frames);
    printf("  %-15s %10s %10s %7s\n", "stage", "wall s", "CPU s", "wall %");
    for (int s = 0; s < ORR_NSTAGES; s++)
        if (t->wall[s] > 0 || t->cpu[s] > 0)
            printf("  %-15s %10.3f %10.3f %6.1f%%\n", orr_stage_name((orr_stage)s), t->wall[s], t->cpu[s],
                   t->total_wall > 0 ? 100.0 * t->wall[s] / t->total_wall : 0.0);
    double wall, cpu;
    orr_stage_times_sum(t, &wall, &cpu);
    printf("  %-15s %10.3f %10.3f\n", "stages summed", wall, cpu);
    printf("  %-15s %10.3f %10.3f  (%.2f CPU per wall second)\n", "total", t->total_wall, t->total_cpu,
           t->total_wall > 0 ? t->total_cpu / t->total_wall : 0.0);
}
