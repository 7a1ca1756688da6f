/* A spherical component's ergodic distribution function f(E) placed in a
 * galaxy's true, flattened potential instead of its spherical average
 * (used by model.c for the bulges).
 *
 * Eddington's inversion (galaxy_df.h) gives f(E) for a Hernquist density
 * rho(r) in the spherically averaged potential psi_sph(r). In the real
 * potential, where the disc pulls harder in its plane than its monopole
 * and less above it, f(E) with E = v^2/2 - psi_true(x) is still a steady
 * state (Jeans' theorem) and its density is rho as a function of the
 * potential alone: rho(x) = rho(r_eq(x)), with r_eq the radius at which
 * psi_sph(r_eq) = psi_true(x). The speeds at x are those of f at r_eq.
 * (Placed spherically, a Milky Way bulge flattened by 20% and grew 6-15%
 * in half-mass radius within 25 Myr of an N-body run.)
 *
 * psi_true = psi_sph - (Phi_disc - Phi_disc_monopole): the disc's potential
 * for its exponential layer, from the Hankel transform of the thin disc
 * (Binney & Tremaine 2008 eq. 2.170 and 2.168) averaged over the vertical
 * profile exp(-|z|/h) / (2h), less its spherical average. The component's
 * own change of shape is not fed back into the potential.
 *
 * Units are the caller's (model.c: kpc, 1e10 Msun, km/s). */
#ifndef ORR_SOURCE_GALAXY_FLAT_H
#define ORR_SOURCE_GALAXY_FLAT_H

#include "source/models/galaxy_df.h"

/* Potential of an exponential disc of finite thickness,
 * rho = Sigma0 exp(-R/rd) exp(-|z|/h) / (2h), at (R, z):
 *   Phi = -2 pi G Sigma0 rd^2 integral_0^inf J0(kR) I(k, z) dk / (1 + k^2 rd^2)^1.5,
 * I(k, z) the vertical average of exp(-k |z - z'|) (1 / (1 + k h) at z = 0).
 * Midpoint rule as gdf_thick_disc_vc2. */
double gdf_thick_disc_potential(double R, double z, double rd, double h, double G_sigma0);

#define GDF_FLAT_NR 32 /* radii, uniform in ln r */
#define GDF_FLAT_NB 16 /* heights above the plane: sin(b) = (j / (NB - 1))^2 */

typedef struct gdf_flat {
    double ln_rmin, dln;
    float ln_ratio[GDF_FLAT_NR][GDF_FLAT_NB]; /* ln(r_eq / r) */
    double bound; /* an upper bound of rho(r_eq) / rho(r): the rejection envelope */
} gdf_flat;

/* The disc and component description gdf_flat_build needs. */
typedef struct gdf_flat_disc {
    double rd, h, G_sigma0;
    const gdf_potential *total;     /* psi_sph: the potential f was built in */
    const gdf_potential *disc_mono; /* psi of the disc's monopole alone */
} gdf_flat_disc;

/* Tabulates r_eq / r for rmin < r < rmax at every height, and the rejection
 * bound for the density rho_fn (as for gdf_speeds_build). */
void gdf_flat_build(gdf_flat *t, const gdf_flat_disc *d, double rmin, double rmax,
                    double (*rho_fn)(double, const void *), const void *ctx);

/* r_eq at radius r and |sin b| = |z| / r (bilinear in ln r and sqrt(sin b);
 * the innermost and outermost radii's values beyond the table). */
double gdf_flat_req(const gdf_flat *t, double r, double sin_b);

#endif
