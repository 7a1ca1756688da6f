/* A branch-free arctangent for the projection loops, which libm's atan2f
 * would keep from vectorising. atan(t) for t in [0, 1] is t P(t^2) with a
 * degree-7 polynomial P fitted for this project (least squares on Chebyshev
 * nodes, reweighted toward the minimax error): the error is below 4e-8 rad
 * in exact arithmetic and 1.9e-7 rad evaluated in float (3.1e-7 for
 * atan2 near +-pi, where pi - atan rounds), about 3e-4 pixel on a
 * 3600-pixel dome master. Other arguments reduce to [0, 1] by
 * atan(t) = pi/2 - atan(1/t) and the quadrant. */
#ifndef ORR_CORE_FASTMATH_H
#define ORR_CORE_FASTMATH_H

#include <math.h>

static inline float orr_atan01f(float t)
{
    /* Estrin's scheme: the pairs, then the pairs of pairs, are independent
     * of each other, so the dependent chain is four multiply-adds long
     * instead of Horner's eight (the dome's projection waits on it). */
    const float t2 = t * t, t4 = t2 * t2, t8 = t4 * t4;
    const float p01 = 0.9999993356069681f - 0.3332986084049284f * t2;
    const float p23 = 0.19946565982406292f - 0.13908630303516115f * t2;
    const float p45 = 0.09642197754258813f - 0.05591231835315513f * t2;
    const float p67 = 0.02186294486781462f - 0.004054562124649386f * t2;
    const float p03 = p01 + p23 * t4, p47 = p45 + p67 * t4;
    return (p03 + p47 * t8) * t;
}

/* atan2(y, x) in (-pi, pi], as libm's up to 3.1e-7; atan2(0, 0) = 0. */
static inline float orr_atan2f(float y, float x)
{
    const float ax = fabsf(x), ay = fabsf(y);
    const float hi = ax > ay ? ax : ay, lo = ax > ay ? ay : ax;
    float a = orr_atan01f(hi > 0.0f ? lo / hi : 0.0f);
    a = ay > ax ? 1.57079632679489662f - a : a;
    a = x < 0.0f ? 3.14159265358979324f - a : a;
    return y < 0.0f ? -a : a;
}

/* 1 when a is a NaN or an infinity. a - a is 0 for a finite a and NaN
 * otherwise; the build honours NaNs, so it is not folded away. Unlike
 * isfinite() it is no branch, and unlike a test of the bits it reads the
 * float itself, so a loop of it vectorises without the compiler fearing
 * the float aliases the loop's outputs. */
static inline int orr_not_finite_f(float a)
{
    return !((a - a) == 0.0f);
}

#endif
