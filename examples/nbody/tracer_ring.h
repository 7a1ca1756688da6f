/* A tracer's pull averaged around its galaxy (--tracer-ring K).
 *
 * Why: the model's Sun is a massless tracer whose path the in-situ camera
 * rides on. In a disc of 10^5 particles, the spirals and bar that particle
 * noise amplifies (kiloparsecs across, far above any softening) torque it,
 * and it migrates 1-2 kpc in radius within 0.2 Gyr, so the sky's light
 * swings with the density around it from frame to frame. The torque is the
 * non-axisymmetric part of the field: its mean around a ring about the
 * galaxy's axis is zero. So a ring tracer feels
 *
 *     a = a_host + < R(-phi_k) (a(x_k) - a_host) >_k
 *
 * where x_k = c + R(phi_k)(x - c), k = 0 .. K-1, are K points on the ring
 * through the tracer about the axis n of its host galaxy through its centre
 * c, R(phi) the rotation about n, and a_host the host's own acceleration
 * (its central stars' mean): the galaxy's axisymmetric pull (radial and
 * vertical), and the uniform pull of everything else (Andromeda), which
 * moves host and tracer alike. Its angular momentum about the axis is then
 * kept but for tides. The host: the stars within a sphere reaching well
 * past the tracer, centred (twice) on their centre of mass from the black
 * hole nearest the tracer (while no other black hole is inside that
 * sphere: see ring_one in nbody.c); its axis the one its disc's particles
 * are thinnest along. The axis is taken from positions alone, not from the
 * disc's spin: at a force computation the velocities are half a step
 * behind, at a resume they are not, and a resume must give the same bits.
 * (The bulge is left out of the axis: it is rounder. Its core sloshes in
 * the halo, so the whole sphere's mean acceleration is the host's.)
 *
 * The functions here are the local parts: sums over this process's own
 * particles, which nbody.c adds over the ranks. */
#ifndef NBODY_TRACER_RING_H
#define NBODY_TRACER_RING_H

#include <stddef.h>
#include <stdint.h>

#define RING_POINTS_MAX 256

/* The squared distance between points a and b. */
double ring_distance2(const double a[3], const double b[3]);

/* out = a x b. */
void ring_cross(const double a[3], const double b[3], double out[3]);

/* Sums over the stars (types 2 and 3) of pos/acc/mass not lighter than
 * light within radius of centre: s[0] mass, s[1..3] m x, s[4..6] m a.
 * Added to s. */
#define RING_SUMS 7
void ring_star_sums(const double *pos, const double *acc, const double *mass, const uint8_t *type, size_t n,
                    double light, const double centre[3], double radius, double s[RING_SUMS]);

/* The second moments m (x - c)_a (x - c)_b (xx, yy, zz, xy, xz, yz) of the
 * particles of type `which` within radius of c: added to m2. */
void ring_shape_sum(const double *pos, const double *mass, const uint8_t *type, size_t n, uint8_t which,
                    const double c[3], double radius, double m2[6]);

/* The axis a flattened shape is thinnest along (the second moments' least
 * eigenvector, by Jacobi rotations) into n, a unit vector of either sign.
 * Returns 0 when the moments are 0. */
int ring_axis(const double m2[6], double n[3]);

/* The stars' centre and mean acceleration from summed ring_star_sums.
 * Returns 0 when the sums hold no mass. */
int ring_host(const double s[RING_SUMS], double c[3], double a[3]);

/* The K points of the ring through x about the axis n through c into
 * pts[0 .. 3K), point k turned by 2 pi k / K (point 0 is x). With mirror
 * (K even) every odd point is then reflected across the disc's plane (the
 * plane through c across n), to the height -z of the tracer's z: see
 * ring_average. */
void ring_points(const double c[3], const double n[3], const double x[3], int k, int mirror, double *pts);

/* G times the softened pulls of particles pos/mass/eps (n of them, those
 * lighter than light left out) at the npts points, the pair softened as
 * (eps_j^2 + eps_t^2) / 2: added to acc[0 .. 3 npts). Direct sums, each
 * point's in the particles' order: the same bits on any thread count. */
void ring_pulls(const double *pos, const double *mass, const double *eps, size_t n, double light, double eps_t,
                const double *pts, int npts, double G, double *acc);

/* a_host + the mean of the K pulls at the ring's points (acc, 3K), each
 * less a_host and turned back to the tracer's place about n, into out.
 * With mirror (the points of ring_points with mirror), the odd points'
 * pulls are first reflected back across the plane. Why: the mean is then
 * that of a galaxy the same above and below its plane, as well as all
 * round its axis. The pull across the plane is zero on it and opposite at
 * z and -z, so a disc's bending waves, warps and clumps off its plane (in
 * a disc of 10^5 particles its local mid-plane wanders by 0.1-0.4 kpc)
 * do not lift the tracer; the noise of the pulls still can. */
void ring_average(const double n[3], const double a_host[3], const double *acc, int k, int mirror, double out[3]);

/* The velocity of a circular orbit through x about the axis n through c,
 * in the pull a (the ring's, ring_average) of a host at c moving at v_host
 * with acceleration a_host: v_host + sqrt(R a_R) t, where R is x's distance
 * from the axis, a_R the inward part of a - a_host across it and t the unit
 * vector along the circle, turning the way v - v_host does about n. Why:
 * the particles' ring-averaged pull at a tracer's softening is not the
 * smooth model's (234 against 239 km/s at the model's Sun, 5 x 10^5
 * particles), so a tracer started on the model's circular speed keeps an
 * epicycle. Returns 0 (out untouched) when a_R is not inward or v - v_host
 * has no part along the circle (no sense of turning given). */
int ring_circular_velocity(const double c[3], const double n[3], const double a_host[3], const double v_host[3],
                           const double x[3], const double a[3], const double v[3], double out[3]);

#endif
