/* The pieces of the optical-depth walk that column.c (one segment at a
 * time) and column_group.c (many segments from one eye, sharing the tree's
 * traversal) both use, so that both give the same value bit for bit.
 * Internal to dust/. */
#ifndef ORR_DUST_COLUMN_WALK_H
#define ORR_DUST_COLUMN_WALK_H

#include <math.h>

#include "dust/column.h"

#define ORR_DUST_SUPPORT 2.0 /* kernel support in units of h (splat/kernel.h) */

typedef struct orr_dust_segment {
    double o[3], d[3]; /* origin, unit direction */
    double len;        /* length (INFINITY: a ray) */
    double inv[3];     /* 1 / d, large and finite where d = 0 */
} orr_dust_segment;

static inline int orr_dust_make_segment(orr_dust_segment *g, const double eye[3], const double dir[3], double len)
{
    double n = sqrt(dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2]);
    if (!(n > 0) || !isfinite(n))
        return 0;
    for (int a = 0; a < 3; a++) {
        g->o[a] = eye[a];
        g->d[a] = dir[a] / n;
        g->inv[a] = fabs(g->d[a]) > 1e-300 ? 1.0 / g->d[a] : 1e300;
    }
    g->len = len;
    return 1;
}

/* The segment from eye to the star p; 0 for a star at the eye (no column). */
static inline int orr_dust_star_segment(orr_dust_segment *g, const double eye[3], const double p[3])
{
    const double d[3] = {p[0] - eye[0], p[1] - eye[1], p[2] - eye[2]};
    return orr_dust_make_segment(g, eye, d, sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]));
}

/* I(beta, |sv|) by bilinear interpolation; beta in [0, 2). */
static inline double orr_dust_half_column(const orr_dust_set *s, double beta, double sv)
{
    const size_t cols = ORR_DUST_PCOL_NS + 1;
    double u = beta * (ORR_DUST_PCOL_NB / ORR_DUST_SUPPORT), v = fabs(sv) * (ORR_DUST_PCOL_NS / ORR_DUST_SUPPORT);
    if (v >= ORR_DUST_PCOL_NS)
        v = ORR_DUST_PCOL_NS - 1e-9;
    int i = (int)u, j = (int)v;
    if (i >= ORR_DUST_PCOL_NB)
        i = ORR_DUST_PCOL_NB - 1;
    double fu = u - i, fv = v - j;
    const float *r0 = s->pcol + (size_t)i * cols + j, *r1 = r0 + cols;
    double a = r0[0] + fv * (r0[1] - r0[0]), b = r1[0] + fv * (r1[1] - r1[0]);
    return a + fu * (b - a);
}

/* P(beta, sv), beta in [0, 2). */
static inline double orr_dust_pcol(const orr_dust_set *s, double beta, double sv)
{
    double half = orr_dust_half_column(s, beta, ORR_DUST_SUPPORT);
    return half + (sv < 0 ? -orr_dust_half_column(s, beta, sv) : orr_dust_half_column(s, beta, sv));
}

/* P(beta, sv) given the whole column F(beta^2) = whole: 0 before the
 * support, F beyond it, F / 2 +- I(beta, |sv|) inside it. A segment that
 * ends inside a kernel (a star in it) so takes one look-up in the partial
 * table, not three (docs/dust.md#cost); F / 2 and I(beta, 2) agree to the
 * tables' accuracy (column.c fills both by the same quadrature). */
static inline double orr_dust_pcol_given(const orr_dust_set *s, double whole, double beta, double sv)
{
    if (sv <= -ORR_DUST_SUPPORT)
        return 0;
    if (sv >= ORR_DUST_SUPPORT)
        return whole;
    const double h = orr_dust_half_column(s, beta, sv);
    return 0.5 * whole + (sv < 0 ? -h : h);
}

/* The whole column at u = beta^2 in [0, 4), linear in u. */
static inline double orr_dust_whole_column(const orr_dust_set *s, double u)
{
    double x = u * (ORR_DUST_FCOL_NU / (ORR_DUST_SUPPORT * ORR_DUST_SUPPORT));
    int i = (int)x;
    if (i >= ORR_DUST_FCOL_NU)
        i = ORR_DUST_FCOL_NU - 1;
    double f = x - i;
    return s->fcol[i] + f * (s->fcol[i + 1] - s->fcol[i]);
}

/* Where the segment passes a kernel with 1/h = ih whose centre is at
 * v = (vx, vy, vz) from the segment's origin (v2 = |v|^2), in units of h:
 * u = the squared closest approach of the line, s0 and s1 the ends measured
 * from the foot. Returns the squared distance of the segment's closest point
 * (an end, or the foot): the kernel adds to the column only where it is
 * below 4 (the support is the open ball of radius 2h). The tree's boxes and
 * the groups' cones (column_group.c) bound that ball, so a walk that skips a
 * kernel by its bounds skips only zeros. */
static inline double orr_dust_meet(const orr_dust_segment *g, double vx, double vy, double vz, double v2, double ih,
                                   double *u, double *s0, double *s1)
{
    const double tc = vx * g->d[0] + vy * g->d[1] + vz * g->d[2];
    const double b2 = v2 - tc * tc;
    *u = (b2 > 0 ? b2 : 0) * ih * ih;
    *s0 = -tc * ih;
    *s1 = (g->len - tc) * ih;
    return *u + (*s1 < 0 ? *s1 * *s1 : *s0 > 0 ? *s0 * *s0 : 0.0);
}

/* The column through a kernel met at (u, s0, s1) (orr_dust_meet), h = 1:
 * the whole column when the segment crosses the support, else the part
 * between its ends. */
static inline double orr_dust_met_column(const orr_dust_set *s, double u, double s0, double s1)
{
    const double whole = orr_dust_whole_column(s, u);
    if (s0 <= -ORR_DUST_SUPPORT && s1 >= ORR_DUST_SUPPORT)
        return whole;
    const double beta = sqrt(u);
    return orr_dust_pcol_given(s, whole, beta, s1) - orr_dust_pcol_given(s, whole, beta, s0);
}

/* The segment's optical depth through a kernel with 1/h = ih and
 * k/h^2 = kih2 whose centre is v = (vx, vy, vz) from the segment's origin
 * (v2 = |v|^2): 0 where the segment misses its support. */
static inline double orr_dust_term(const orr_dust_set *s, const orr_dust_segment *g, double vx, double vy, double vz,
                                   double v2, double ih, double kih2)
{
    double u, s0, s1;
    if (orr_dust_meet(g, vx, vy, vz, v2, ih, &u, &s0, &s1) >= ORR_DUST_SUPPORT * ORR_DUST_SUPPORT)
        return 0;
    return kih2 * orr_dust_met_column(s, u, s0, s1);
}

/* The share of the segment's optical depth of a kernel at (x, y, z) with
 * 1/h = ih and k/h^2 = kih2. */
static inline double orr_dust_share(const orr_dust_set *s, const orr_dust_segment *g, double x, double y, double z,
                                    double ih, double kih2)
{
    const double vx = x - g->o[0], vy = y - g->o[1], vz = z - g->o[2];
    return orr_dust_term(s, g, vx, vy, vz, vx * vx + vy * vy + vz * vz, ih, kih2);
}

#endif
