/* The fused gather of nearest-pixel deposits: for a block of particles
 * that the view takes whole (every type drawn, no observer among them),
 * one loop reads each particle's position and weight, checks they are
 * finite, moves it into the camera frame, projects it and makes its NGP
 * pixel index (splat/deposit.h), where the general gather makes a pass
 * over the block for each of these steps. The weights are not copied
 * unless dimmed. It is the hot loop of nearest-pixel renders
 * (docs/performance.md), and gives the same indices, bit for bit, as the
 * general passes. */
#ifndef ORR_PASS_NGP_GATHER_H
#define ORR_PASS_NGP_GATHER_H

#include <stddef.h>
#include <stdint.h>

#include "frame/projection.h"
#include "pass/camera_transform.h"
#include "splat/deposit.h"

typedef struct orr_ngp_gather_out {
    int32_t *index;   /* n: pixel, ORR_NGP_OFF or ORR_NGP_CULLED */
    float *px, *py;   /* n each: positions, written for sky maps only (orr_ngp_place reads them) */
    float *dimming;   /* n: with t->dim, each particle's 1/r^2 factor */
} orr_ngp_gather_out;

/* Gathers particles [0, n) of x, y, z (and w, only checked) through t and
 * p onto the image of outline m. Returns 1, or 0 when some position or
 * weight is not finite: then nothing it wrote may be used, and the block
 * goes the general way, which reports or skips the particle. */
int orr_ngp_gather(const orr_projection *p, const orr_map_outline *m, const orr_camera_transform *t, size_t n,
                   const float *x, const float *y, const float *z, const float *w, const orr_ngp_gather_out *out);

#endif
