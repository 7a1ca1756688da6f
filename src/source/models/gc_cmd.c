/* A schematic colour-magnitude diagram of an old, metal-poor globular
 * cluster, shaped after M3 (NGC 5272, [Fe/H] = -1.5).
 *
 * Sources of the shape (docs/nightfall.md has the full discussion):
 * - anchors from W. E. Harris, "A catalog of parameters for globular clusters
 *   in the Milky Way" (1996, AJ 112, 1487; 2010 edition) for M3:
 *   V_HB = 15.64, (m-M)_V = 15.07, E(B-V) = 0.01, HB ratio
 *   (B-R)/(B+V+R) = 0.08, so M_V(HB) = 0.57;
 * - the turnoff (V ~ 19.1, i.e. M_V ~ 4.0, (B-V)_0 ~ 0.42), the subgiant
 *   branch, the red giant branch up to its tip (V ~ 12.6, B-V ~ 1.5) and the
 *   asymptotic giant branch read off the M3 diagrams of Buonanno et al.
 *   (1994, A&A 290, 69) and Ferraro et al. (1997, A&A 320, 757) to about
 *   0.05 mag: a schematic line through the sequences, not a fit;
 * - the number ratio R = N_HB / N_RGB(brighter than the HB) ~ 1.4 and
 *   N_AGB / N_HB ~ 0.12 of evolved stars in old clusters (Buzzoni et al.
 *   1983, A&A 128, 94; Buonanno et al. 1994 for M3).
 * The magnitudes are absolute (M_V) and the colours intrinsic, so the
 * renderer's 1/r^2 dimming supplies the distance. */
#include "source/models/gc_cmd.h"

#include <math.h>

typedef struct cmd_node {
    double mv, bv;
} cmd_node;

/* Fiducial lines, faint to bright (mv decreasing). */
static const cmd_node MAIN_SEQUENCE[] = {
    {10.0, 1.40}, {8.0, 1.05}, {7.0, 0.88}, {6.0, 0.72}, {5.0, 0.58}, {4.5, 0.50}, {4.0, 0.42},
};
static const cmd_node SUBGIANT[] = {
    {4.0, 0.42}, {3.6, 0.50}, {3.3, 0.62}, {3.1, 0.72},
};
static const cmd_node RED_GIANT[] = {
    {3.1, 0.72}, {2.0, 0.78}, {1.0, 0.83}, {0.0, 0.90}, {-1.0, 1.03}, {-2.0, 1.25}, {-2.5, 1.48},
};
static const cmd_node ASYMPTOTIC_GIANT[] = {
    {0.4, 0.72}, {-0.5, 0.80}, {-1.0, 0.88}, {-1.8, 1.08},
};

#define NODES(a) ((int)(sizeof(a) / sizeof((a)[0])))

/* Number fractions of the phases (stars from M_V = 10 up). The red giants
 * follow the fuel-consumption theorem (Renzini & Buzzoni 1986): about 2e-11
 * stars per year per solar luminosity leave the main sequence, and a
 * population of M/L_V ~ 2 has some 1.5 stars brighter than M_V = 10 per
 * Lsun, so a phase lasting t holds ~1.3e-11 t / yr of the stars: 0.5% for
 * the ~4e8 yr red giant branch, 0.13% for the ~1e8 yr horizontal branch.
 * Then R = N_HB / N_RGB(brighter than the HB) = 1.35 with the giants'
 * luminosity function below, and N_AGB / N_HB = 0.12. The rest is the main
 * sequence. */
#define FRAC_SUBGIANT 0.004
#define FRAC_RED_GIANT 0.006
#define FRAC_HB 0.0013
#define FRAC_AGB 0.00016
#define FRAC_MAIN_SEQUENCE (1.0 - FRAC_SUBGIANT - FRAC_RED_GIANT - FRAC_HB - FRAC_AGB)

/* Luminosity functions dN/dM_V ~ 10^(slope M_V): the red giant branch's
 * ~0.3 is the usual fuel-consumption slope (the LF of M3's giants rises by
 * about a factor 2 per magnitude); the main sequence's is shallower. */
#define LF_SLOPE_MAIN_SEQUENCE 0.12
#define LF_SLOPE_RED_GIANT 0.30
#define LF_SLOPE_AGB 0.30

/* HB split blue : RR Lyrae : red for M3 (B, V, R of Harris's HB ratio
 * (B-R)/(B+V+R) = 0.08 with V ~ 0.42), and the colour ranges of each. */
#define HB_BLUE 0.33
#define HB_VARIABLE 0.42
#define HB_MV 0.57
#define HB_BLUE_MIN (-0.05)
#define HB_BLUE_MAX 0.18
#define HB_RED_MAX 0.62
#define HB_RR_MAX 0.42

/* Intrinsic width of the sequences (binaries, abundance spread). */
#define SCATTER_BV 0.015
#define SCATTER_MV 0.03

double orr_gc_phase_fraction(orr_gc_phase phase)
{
    switch (phase) {
    case ORR_GC_MAIN_SEQUENCE: return FRAC_MAIN_SEQUENCE;
    case ORR_GC_SUBGIANT: return FRAC_SUBGIANT;
    case ORR_GC_RED_GIANT: return FRAC_RED_GIANT;
    case ORR_GC_HORIZONTAL_BRANCH: return FRAC_HB;
    case ORR_GC_ASYMPTOTIC_GIANT: return FRAC_AGB;
    }
    return 0.0;
}

/* Linear interpolation along a line given faint to bright; clamped. */
static double line_bv(const cmd_node *line, int n, double mv)
{
    if (mv >= line[0].mv)
        return line[0].bv;
    for (int i = 1; i < n; i++)
        if (mv >= line[i].mv) {
            double f = (line[i - 1].mv - mv) / (line[i - 1].mv - line[i].mv);
            return line[i - 1].bv + f * (line[i].bv - line[i - 1].bv);
        }
    return line[n - 1].bv;
}

double orr_gc_fiducial_bv(orr_gc_phase phase, double mv)
{
    switch (phase) {
    case ORR_GC_MAIN_SEQUENCE: return line_bv(MAIN_SEQUENCE, NODES(MAIN_SEQUENCE), mv);
    case ORR_GC_SUBGIANT: return line_bv(SUBGIANT, NODES(SUBGIANT), mv);
    case ORR_GC_RED_GIANT: return line_bv(RED_GIANT, NODES(RED_GIANT), mv);
    case ORR_GC_ASYMPTOTIC_GIANT: return line_bv(ASYMPTOTIC_GIANT, NODES(ASYMPTOTIC_GIANT), mv);
    case ORR_GC_HORIZONTAL_BRANCH: break;
    }
    return NAN;
}

/* M_V with density ~ 10^(slope M_V) between bright and faint (inverse CDF). */
static double draw_power_lf(orr_rng *r, double slope, double bright, double faint)
{
    double lo = pow(10.0, slope * bright), hi = pow(10.0, slope * faint);
    return log10(lo + orr_rng_uniform(r) * (hi - lo)) / slope;
}

/* The horizontal branch: a colour drawn within the blue, variable (RR Lyrae,
 * at their mean colour) or red part; a level branch, drooping slightly
 * blueward of B-V = 0.1 as the hotter stars' bolometric corrections grow. */
static void draw_horizontal_branch(orr_rng *r, orr_gc_star *s)
{
    double part = orr_rng_uniform(r), u = orr_rng_uniform(r);
    if (part < HB_BLUE)
        s->bv = HB_BLUE_MIN + u * (HB_BLUE_MAX - HB_BLUE_MIN);
    else if (part < HB_BLUE + HB_VARIABLE)
        s->bv = HB_BLUE_MAX + u * (HB_RR_MAX - HB_BLUE_MAX);
    else
        s->bv = HB_RR_MAX + u * (HB_RED_MAX - HB_RR_MAX);
    double blue = s->bv < 0.10 ? 0.10 - s->bv : 0.0;
    s->mv = HB_MV + 6.0 * blue * blue;
}

orr_gc_star orr_gc_draw(orr_rng *r)
{
    orr_gc_star s;
    double u = orr_rng_uniform(r);
    double c_ms = FRAC_MAIN_SEQUENCE, c_sg = c_ms + FRAC_SUBGIANT, c_rg = c_sg + FRAC_RED_GIANT;
    double c_hb = c_rg + FRAC_HB;
    if (u < c_ms) {
        s.phase = ORR_GC_MAIN_SEQUENCE;
        s.mv = draw_power_lf(r, LF_SLOPE_MAIN_SEQUENCE, MAIN_SEQUENCE[NODES(MAIN_SEQUENCE) - 1].mv,
                             MAIN_SEQUENCE[0].mv);
    } else if (u < c_sg) {
        s.phase = ORR_GC_SUBGIANT; /* crossed at a steady pace: uniform in M_V */
        s.mv = SUBGIANT[0].mv + orr_rng_uniform(r) * (SUBGIANT[NODES(SUBGIANT) - 1].mv - SUBGIANT[0].mv);
    } else if (u < c_rg) {
        s.phase = ORR_GC_RED_GIANT;
        s.mv = draw_power_lf(r, LF_SLOPE_RED_GIANT, RED_GIANT[NODES(RED_GIANT) - 1].mv, RED_GIANT[0].mv);
    } else if (u < c_hb) {
        s.phase = ORR_GC_HORIZONTAL_BRANCH;
        draw_horizontal_branch(r, &s);
    } else {
        s.phase = ORR_GC_ASYMPTOTIC_GIANT;
        s.mv = draw_power_lf(r, LF_SLOPE_AGB, ASYMPTOTIC_GIANT[NODES(ASYMPTOTIC_GIANT) - 1].mv,
                             ASYMPTOTIC_GIANT[0].mv);
    }
    if (s.phase != ORR_GC_HORIZONTAL_BRANCH)
        s.bv = orr_gc_fiducial_bv(s.phase, s.mv);
    double g0, g1;
    orr_rng_gauss2(r, &g0, &g1);
    s.bv += SCATTER_BV * g0;
    s.mv += SCATTER_MV * g1;
    return s;
}
