/* Tests of src/source/models/galaxy_flat.c against independent results: the thick
 * exponential disc's potential against Freeman's thin-disc potential in the
 * thin limit, against a point mass far away, against Poisson's equation
 * inside the layer (a numerical Laplacian must give back 4 pi G rho), and
 * its radial force against the rotation curve of galaxy_df.c; and the
 * equivalent radii of a sphere's f(E) in the disc's flattened potential. */
#include <math.h>
#include <stdlib.h>

#include "check.h"
#include "source/models/galaxy_flat.h"

#define PI 3.14159265358979323846

/* Freeman (1970), Binney & Tremaine 2008 eq. 2.164a: in the plane of a
 * razor-thin exponential disc, Phi = -pi G Sigma0 R [I0 K1 - I1 K0](R / 2rd). */
static double freeman_potential(double R, double rd, double G_sigma0)
{
    double y = R / (2.0 * rd);
    return -PI * G_sigma0 * R *
           (gdf_bessel_i0(y) * gdf_bessel_k1(y) - gdf_bessel_i1(y) * gdf_bessel_k0(y));
}

static void test_thin_limit(void)
{
    const double rd = 3.0;
    for (double R = 0.5; R < 30.0; R *= 1.8)
        CHECK_NEAR(gdf_thick_disc_potential(R, 0.0, rd, 3e-4, 1.0) / freeman_potential(R, rd, 1.0), 1.0,
                   1e-3);
}

/* Far away the disc is a point of mass 2 pi Sigma0 rd^2 (quadrupole ~1e-4). */
static void test_far_field(void)
{
    const double rd = 3.0, h = 0.3, R = 300.0, z = 400.0;
    double gm = 2.0 * PI * rd * rd;
    CHECK_NEAR(gdf_thick_disc_potential(R, z, rd, h, 1.0) / (-gm / 500.0), 1.0, 1e-3);
}

/* (1/R) d/dR (R dPhi/dR) + d^2Phi/dz^2 = 4 pi G Sigma0 e^(-R/rd) e^(-|z|/h) / (2h),
 * by central differences, in the layer and above it. */
static void test_poisson(void)
{
    const double rd = 3.0, h = 0.3, d = 0.01;
    const double pts[][2] = {{2.0, 0.15}, {5.0, 0.4}, {8.0, 0.05}};
    for (int k = 0; k < 3; k++) {
        double R = pts[k][0], z = pts[k][1];
#define P(r, zz) gdf_thick_disc_potential((r), (zz), rd, h, 1.0)
        double c = P(R, z);
        double dr_out = (P(R + d, z) - c) / d, dr_in = (c - P(R - d, z)) / d;
        double radial = ((R + d / 2) * dr_out - (R - d / 2) * dr_in) / (R * d);
        double vertical = (P(R, z + d) - 2.0 * c + P(R, z - d)) / (d * d);
#undef P
        double rho = exp(-R / rd) * exp(-z / h) / (2.0 * h);
        CHECK_NEAR((radial + vertical) / (4.0 * PI * rho), 1.0, 0.01);
    }
}

/* R dPhi/dR in the plane is galaxy_df.c's thick-disc v_c^2 (another integral). */
static void test_rotation(void)
{
    const double rd = 3.0, h = 0.3;
    for (double R = 0.5; R < 20.0; R *= 2.0) {
        double e = 1e-3 * R;
        double dphi = (gdf_thick_disc_potential(R + e, 0, rd, h, 1.0) -
                       gdf_thick_disc_potential(R - e, 0, rd, h, 1.0)) / (2 * e);
        CHECK_NEAR(R * dphi / gdf_thick_disc_vc2(R, rd, h, 1.0), 1.0, 2e-3);
    }
}

/* A Hernquist sphere (G = M = a = 1) plus a disc of mass md, rd = 1.5,
 * h = 0.15, whose monopole is the thin disc's cylinder mass (the test
 * only needs psi_sph and psi_mono consistent with each other). */
typedef struct flat_case {
    double md, rd, h;
} flat_case;

static double disc_mass_within(const flat_case *c, double r)
{
    double x = r / c->rd;
    return c->md * (1.0 - (1.0 + x) * exp(-x));
}
static double gm_total(double r, const void *ctx)
{
    return r * r / ((1 + r) * (1 + r)) + disc_mass_within(ctx, r);
}
static double gm_disc(double r, const void *ctx)
{
    return disc_mass_within(ctx, r);
}
static double rho_hernquist(double r, const void *ctx)
{
    (void)ctx;
    return 1.0 / (r * (1 + r) * (1 + r) * (1 + r));
}

typedef struct flat_tables {
    gdf_potential total, mono;
    gdf_flat t;
} flat_tables;

static flat_tables *build_case(const flat_case *c)
{
    flat_tables *f = malloc(sizeof *f);
    CHECK(f != NULL);
    gdf_potential_build(&f->total, 1e-4, 1e4, gm_total, c);
    gdf_potential_build(&f->mono, 1e-4, 1e4, gm_disc, c);
    gdf_flat_disc d = {c->rd, c->h, c->md / (2 * PI * c->rd * c->rd), &f->total, &f->mono};
    gdf_flat_build(&f->t, &d, 1e-2, 10.0, rho_hernquist, NULL);
    return f;
}

static void test_equivalent_radius(void)
{
    /* A massless disc leaves the sphere as it was. */
    flat_case none = {0.0, 1.5, 0.15};
    flat_tables *f = build_case(&none);
    CHECK_NEAR(gdf_flat_req(&f->t, 0.7, 0.0) / 0.7, 1.0, 1e-4);
    CHECK_NEAR(gdf_flat_req(&f->t, 3.0, 1.0) / 3.0, 1.0, 1e-4);
    CHECK_NEAR(f->t.bound, 1.05, 1e-4);
    free(f);

    /* A disc of half the sphere's mass: the plane is deeper than the
     * monopole (r_eq < r, denser), the axis shallower; r_eq between the
     * table's nodes matches psi_sph(r_eq) = psi_true computed directly. */
    flat_case half = {0.5, 1.5, 0.15};
    f = build_case(&half);
    double G_sigma0 = half.md / (2 * PI * half.rd * half.rd);
    CHECK(gdf_flat_req(&f->t, 1.0, 0.0) < 0.97);
    CHECK(gdf_flat_req(&f->t, 1.0, 1.0) > 1.01);
    CHECK(f->t.bound > 1.1);
    const double pts[][2] = {{0.37, 0.05}, {1.3, 0.2}, {2.9, 0.5}, {6.1, 0.93}};
    for (int k = 0; k < 4; k++) {
        double r = pts[k][0], sb = pts[k][1], z = r * sb, R = r * sqrt(1 - sb * sb);
        double psi_true = gdf_psi(&f->total, r) - gdf_psi(&f->mono, r) -
                          gdf_thick_disc_potential(R, z, half.rd, half.h, G_sigma0);
        double req = gdf_flat_req(&f->t, r, sb);
        double dpsi = gdf_psi(&f->total, r) - psi_true; /* the disc's departure */
        CHECK_NEAR((gdf_psi(&f->total, r) - gdf_psi(&f->total, req)) / dpsi, 1.0, 0.1);
    }
    free(f);
}

int main(void)
{
    RUN(test_thin_limit);
    RUN(test_far_field);
    RUN(test_poisson);
    RUN(test_rotation);
    RUN(test_equivalent_radius);
    return check_summary();
}
