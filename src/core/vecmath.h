/* Vectors, 3x3 matrices and unit quaternions in double precision.
 * Conventions: matrices act on column vectors (v' = M v), m[row][col].
 * A quaternion q = (w, x, y, z) represents the rotation v' = q v q*. */
#ifndef ORR_CORE_VECMATH_H
#define ORR_CORE_VECMATH_H

#include <math.h>

#define ORR_PI 3.14159265358979323846

typedef struct { double x, y, z; } orr_vec3;
typedef struct { double m[3][3]; } orr_mat3;
typedef struct { double w, x, y, z; } orr_quat;

/* A table of n >= 2 entries read at fractional position u: u is clamped to
 * [0, n - 1]; returns the cell i (0 .. n - 2) and sets *frac = u - i, the
 * weight of entry i + 1 in a linear interpolation. */
static inline int orr_table_cell(double u, int n, double *frac)
{
    if (u < 0)
        u = 0;
    if (u > n - 1)
        u = n - 1;
    int i = (int)u;
    if (i > n - 2)
        i = n - 2;
    *frac = u - i;
    return i;
}

static inline orr_vec3 orr_v3(double x, double y, double z) { return (orr_vec3){x, y, z}; }
static inline orr_vec3 orr_v3_add(orr_vec3 a, orr_vec3 b) { return orr_v3(a.x + b.x, a.y + b.y, a.z + b.z); }
static inline orr_vec3 orr_v3_sub(orr_vec3 a, orr_vec3 b) { return orr_v3(a.x - b.x, a.y - b.y, a.z - b.z); }
static inline orr_vec3 orr_v3_scale(orr_vec3 a, double s) { return orr_v3(a.x * s, a.y * s, a.z * s); }
static inline double orr_v3_dot(orr_vec3 a, orr_vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static inline double orr_v3_norm(orr_vec3 a) { return sqrt(orr_v3_dot(a, a)); }
static inline orr_vec3 orr_v3_cross(orr_vec3 a, orr_vec3 b)
{
    return orr_v3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}
/* Returns a / |a|, or the zero vector when |a| is zero. */
static inline orr_vec3 orr_v3_normalize(orr_vec3 a)
{
    double n = orr_v3_norm(a);
    return n > 0 ? orr_v3_scale(a, 1.0 / n) : orr_v3(0, 0, 0);
}

orr_mat3 orr_mat3_identity(void);
orr_mat3 orr_mat3_mul(orr_mat3 a, orr_mat3 b);
orr_mat3 orr_mat3_transpose(orr_mat3 a);
orr_vec3 orr_mat3_apply(orr_mat3 m, orr_vec3 v);
/* Rotation by angle (radians) about a unit axis, right-handed. */
orr_mat3 orr_mat3_axis_angle(orr_vec3 axis, double angle);
/* The matrix whose rows are r0, r1, r2. */
orr_mat3 orr_mat3_from_rows(orr_vec3 r0, orr_vec3 r1, orr_vec3 r2);

orr_quat orr_quat_identity(void);
/* Rotation by angle (radians) about axis (need not be normalised; a zero axis
 * gives the identity). */
orr_quat orr_quat_axis_angle(orr_vec3 axis, double angle);
orr_quat orr_quat_mul(orr_quat a, orr_quat b);
orr_quat orr_quat_conj(orr_quat q);
orr_quat orr_quat_normalize(orr_quat q);
orr_vec3 orr_quat_rotate(orr_quat q, orr_vec3 v);
orr_mat3 orr_quat_to_mat3(orr_quat q);
/* The unit quaternion of a proper rotation matrix (Shepperd's method). */
orr_quat orr_quat_from_mat3(orr_mat3 m);
/* Spherical linear interpolation along the shorter arc; t = 0 gives a,
 * t = 1 gives b (or -b, the same rotation). */
orr_quat orr_quat_slerp(orr_quat a, orr_quat b, double t);

#endif
