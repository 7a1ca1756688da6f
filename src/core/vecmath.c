#include "core/vecmath.h"

orr_mat3 orr_mat3_identity(void)
{
    return (orr_mat3){{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
}

orr_mat3 orr_mat3_mul(orr_mat3 a, orr_mat3 b)
{
    orr_mat3 r;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            r.m[i][j] = a.m[i][0] * b.m[0][j] + a.m[i][1] * b.m[1][j] + a.m[i][2] * b.m[2][j];
    return r;
}

orr_mat3 orr_mat3_transpose(orr_mat3 a)
{
    orr_mat3 r;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            r.m[i][j] = a.m[j][i];
    return r;
}

orr_vec3 orr_mat3_apply(orr_mat3 m, orr_vec3 v)
{
    return orr_v3(m.m[0][0] * v.x + m.m[0][1] * v.y + m.m[0][2] * v.z,
                  m.m[1][0] * v.x + m.m[1][1] * v.y + m.m[1][2] * v.z,
                  m.m[2][0] * v.x + m.m[2][1] * v.y + m.m[2][2] * v.z);
}

orr_mat3 orr_mat3_axis_angle(orr_vec3 axis, double angle)
{
    /* Rodrigues' formula: R = c I + s [a]x + (1 - c) a a^T. */
    orr_vec3 a = orr_v3_normalize(axis);
    double c = cos(angle), s = sin(angle), t = 1.0 - c;
    orr_mat3 r = {{
        {c + t * a.x * a.x, t * a.x * a.y - s * a.z, t * a.x * a.z + s * a.y},
        {t * a.x * a.y + s * a.z, c + t * a.y * a.y, t * a.y * a.z - s * a.x},
        {t * a.x * a.z - s * a.y, t * a.y * a.z + s * a.x, c + t * a.z * a.z},
    }};
    return r;
}

orr_mat3 orr_mat3_from_rows(orr_vec3 r0, orr_vec3 r1, orr_vec3 r2)
{
    return (orr_mat3){{{r0.x, r0.y, r0.z}, {r1.x, r1.y, r1.z}, {r2.x, r2.y, r2.z}}};
}

orr_quat orr_quat_identity(void)
{
    return (orr_quat){1, 0, 0, 0};
}

orr_quat orr_quat_axis_angle(orr_vec3 axis, double angle)
{
    orr_vec3 a = orr_v3_normalize(axis);
    double s = sin(0.5 * angle);
    return orr_quat_normalize((orr_quat){cos(0.5 * angle), a.x * s, a.y * s, a.z * s});
}

orr_quat orr_quat_mul(orr_quat a, orr_quat b)
{
    return (orr_quat){
        a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z,
        a.w * b.x + a.x * b.w + a.y * b.z - a.z * b.y,
        a.w * b.y - a.x * b.z + a.y * b.w + a.z * b.x,
        a.w * b.z + a.x * b.y - a.y * b.x + a.z * b.w,
    };
}

orr_quat orr_quat_conj(orr_quat q)
{
    return (orr_quat){q.w, -q.x, -q.y, -q.z};
}

orr_quat orr_quat_normalize(orr_quat q)
{
    double n = sqrt(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z);
    if (n == 0)
        return orr_quat_identity();
    return (orr_quat){q.w / n, q.x / n, q.y / n, q.z / n};
}

orr_vec3 orr_quat_rotate(orr_quat q, orr_vec3 v)
{
    orr_quat p = {0, v.x, v.y, v.z};
    orr_quat r = orr_quat_mul(orr_quat_mul(q, p), orr_quat_conj(q));
    return orr_v3(r.x, r.y, r.z);
}

orr_mat3 orr_quat_to_mat3(orr_quat q)
{
    q = orr_quat_normalize(q);
    double w = q.w, x = q.x, y = q.y, z = q.z;
    orr_mat3 r = {{
        {1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)},
        {2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)},
        {2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)},
    }};
    return r;
}

orr_quat orr_quat_from_mat3(orr_mat3 a)
{
    /* Pick the largest of w, x, y, z to divide by, for accuracy. */
    const double (*m)[3] = a.m;
    double tr = m[0][0] + m[1][1] + m[2][2];
    orr_quat q;
    if (tr > m[0][0] && tr > m[1][1] && tr > m[2][2]) {
        double s = 2.0 * sqrt(1.0 + tr);
        q = (orr_quat){0.25 * s, (m[2][1] - m[1][2]) / s, (m[0][2] - m[2][0]) / s,
                       (m[1][0] - m[0][1]) / s};
    } else if (m[0][0] > m[1][1] && m[0][0] > m[2][2]) {
        double s = 2.0 * sqrt(1.0 + m[0][0] - m[1][1] - m[2][2]);
        q = (orr_quat){(m[2][1] - m[1][2]) / s, 0.25 * s, (m[0][1] + m[1][0]) / s,
                       (m[0][2] + m[2][0]) / s};
    } else if (m[1][1] > m[2][2]) {
        double s = 2.0 * sqrt(1.0 + m[1][1] - m[0][0] - m[2][2]);
        q = (orr_quat){(m[0][2] - m[2][0]) / s, (m[0][1] + m[1][0]) / s, 0.25 * s,
                       (m[1][2] + m[2][1]) / s};
    } else {
        double s = 2.0 * sqrt(1.0 + m[2][2] - m[0][0] - m[1][1]);
        q = (orr_quat){(m[1][0] - m[0][1]) / s, (m[0][2] + m[2][0]) / s,
                       (m[1][2] + m[2][1]) / s, 0.25 * s};
    }
    q = orr_quat_normalize(q);
    if (q.w < 0) /* a canonical sign makes printed orientations reproducible */
        q = (orr_quat){-q.w, -q.x, -q.y, -q.z};
    return q;
}

orr_quat orr_quat_slerp(orr_quat a, orr_quat b, double t)
{
    a = orr_quat_normalize(a);
    b = orr_quat_normalize(b);
    double d = a.w * b.w + a.x * b.x + a.y * b.y + a.z * b.z;
    if (d < 0) { /* q and -q are the same rotation: take the shorter arc */
        b = (orr_quat){-b.w, -b.x, -b.y, -b.z};
        d = -d;
    }
    double wa, wb;
    if (d > 0.9995) { /* nearly parallel: linear interpolation is exact enough */
        wa = 1.0 - t;
        wb = t;
    } else {
        double theta = acos(d);
        double s = sin(theta);
        wa = sin((1.0 - t) * theta) / s;
        wb = sin(t * theta) / s;
    }
    return orr_quat_normalize((orr_quat){wa * a.w + wb * b.w, wa * a.x + wb * b.x,
                                         wa * a.y + wb * b.y, wa * a.z + wb * b.z});
}
