/* Building blocks for equilibrium galaxy models (used by model.c):
 *
 *  - the circular speed of a razor-thin exponential disc (Freeman 1970),
 *    from modified Bessel functions;
 *  - a spherical potential tabulated from an enclosed-mass function;
 *  - isotropic distribution functions of spherical components by
 *    Eddington's inversion in that potential, turned into per-radius inverse
 *    cumulative tables of speed, so drawing a velocity costs one uniform
 *    number and a few interpolations.
 *
 * Units are the caller's (model.c: kpc, 1e10 Msun, km/s). */
#ifndef ORR_SOURCE_GALAXY_DF_H
#define ORR_SOURCE_GALAXY_DF_H

/* Modified Bessel functions I0, I1, K0, K1 (x > 0 for K), from the
 * polynomial approximations of Abramowitz & Stegun (1964) 9.8.1-9.8.8,
 * relative error below ~2e-7. */
double gdf_bessel_i0(double x);
double gdf_bessel_i1(double x);
double gdf_bessel_k0(double x);
double gdf_bessel_k1(double x);

/* v_c^2 in the plane of a razor-thin exponential disc of central surface
 * density sigma0 and scale length rd at radius R (Freeman 1970; Binney &
 * Tremaine 2008 eq. 2.165): 4 pi G sigma0 rd y^2 [I0 K0 - I1 K1](y),
 * y = R / (2 rd). */
double gdf_freeman_vc2(double R, double rd, double G_sigma0);

/* v_c^2 in the midplane of an exponential disc of finite thickness,
 * rho = Sigma0 exp(-R/rd) exp(-|z|/h) / (2h), from the Hankel-transform
 * potential of the thin disc (Binney & Tremaine 2008 eq. 2.170) averaged
 * over the vertical profile, which multiplies each wavenumber k by
 * 1 / (1 + k h):
 *   v_c^2 = 2 pi G Sigma0 rd^2 R integral_0^inf k J1(kR) dk / ((1 + k^2 rd^2)^1.5 (1 + k h)).
 * Midpoint rule on 0 < k < min(20/h, 2000/rd), at least 4000 points and
 * 20 per period of J1(kR) (relative error < 3e-4 for R > 0.05 h; the cost
 * grows with R/h, so callers use the thin-disc formula far out). The thickness lowers v_c^2 by 5-15% within
 * 3 rd for h = rd / 10; a model rotating at the thin-disc speed is not in
 * equilibrium. */
double gdf_thick_disc_vc2(double R, double rd, double h, double G_sigma0);

/* A spherical potential on a grid uniform in ln r: psi = -Phi >= 0 (the
 * "relative potential" of Binney & Tremaine), and G M(<r). */
#define GDF_POT_N 1024
typedef struct gdf_potential {
    double ln_rmin, dln;
    double psi[GDF_POT_N];  /* decreasing outward */
    double gm[GDF_POT_N];   /* G M(<r) */
} gdf_potential;

/* Tabulates psi from G M(<r) (mass_fn(r, ctx) returns G M(<r)) between rmin
 * and rmax; beyond rmax all the mass is assumed enclosed (psi = G M / r). */
void gdf_potential_build(gdf_potential *p, double rmin, double rmax, double (*gm_fn)(double, const void *),
                         const void *ctx);
double gdf_psi(const gdf_potential *p, double r);
/* The same with ln r given (a caller that has it saves the logarithm). */
double gdf_psi_ln(const gdf_potential *p, double r, double ln_r);

/* Isotropic speed distribution of a spherical component with density
 * rho(r) in the potential p: Eddington's formula (Binney & Tremaine 2008
 * eq. 4.46b),
 *   f(E) = 1/(sqrt(8) pi^2) integral_0^E d^2rho/dpsi^2 dpsi / sqrt(E - psi),
 * (the boundary term vanishes for densities falling faster than r^-3), and
 * from it, at GDF_ROWS radii between rmin and rmax, the inverse cumulative
 * distribution of q = v / v_esc, p(q) ~ q^2 f(psi (1 - q^2)). */
#define GDF_ROWS 256
#define GDF_COLS 128
typedef struct gdf_speeds {
    double ln_rmin, dln;
    float q[GDF_ROWS][GDF_COLS]; /* q at cumulative probability 1 - (1 - j / (GDF_COLS - 1))^2 */
    int negative_f;              /* grid points where f < 0 was clipped (0 for a consistent model) */
} gdf_speeds;

/* rho_fn(r, ctx) and its logarithmic slope dlnrho_fn(r, ctx) = d ln rho / d ln r
 * (analytic, so dRho/dPsi needs no numerical derivative). Returns 0 on
 * allocation failure. */
int gdf_speeds_build(gdf_speeds *s, const gdf_potential *p, double rmin, double rmax,
                     double (*rho_fn)(double, const void *), double (*dlnrho_fn)(double, const void *),
                     const void *ctx);

/* A speed at radius r from one uniform number u in [0, 1): q(u) interpolated
 * between the two nearest rows, times the local escape speed. */
double gdf_speed(const gdf_speeds *s, const gdf_potential *p, double r, double u);
double gdf_speed_ln(const gdf_speeds *s, const gdf_potential *p, double r, double ln_r, double u);

#endif
