/* The stars that a solar mass of the Galaxy's disc stands for: the solar
 * neighbourhood's luminosity function in V per solar mass, its counts and
 * light brighter than any absolute magnitude, and each star's colour
 * (docs/sky.md, "Stars from particles").
 *
 * The table is the solar neighbourhood's stellar luminosity function
 * phi(M_V), stars per pc^3 per magnitude, with its mass density, from
 * Allen's Astrophysical Quantities (3rd ed., 1973, section 117, "Stellar
 * luminosity function, emission function and star density"). Divided by
 * the same table's mass density (0.0437 solar masses per pc^3) it is the
 * number of stars per solar mass of the local disc: 2.98 stars of every
 * magnitude, 1.29 solar V luminosities, 1.1e-2 stars brighter than
 * M_V = 1.5. */
#ifndef ORR_STARS_LUMINOSITY_H
#define ORR_STARS_LUMINOSITY_H

/* The absolute V magnitude of the Sun (as core/ssp.h). */
#define ORR_LF_SUN_MV 4.83

/* The absolute magnitudes the table covers: its bins, one magnitude wide,
 * are centred on -6 ... +22. */
#define ORR_LF_M_BRIGHT (-6.5)
#define ORR_LF_M_FAINT 22.5
/* The cumulative tables' step, magnitudes. */
#define ORR_LF_STEP 0.02
#define ORR_LF_STEPS 1450 /* (ORR_LF_M_FAINT - ORR_LF_M_BRIGHT) / ORR_LF_STEP */

typedef struct orr_lf {
    /* Per solar mass, the stars brighter than M = ORR_LF_M_BRIGHT + k step
     * (k = 0 .. ORR_LF_STEPS): their number and V light (solar units). */
    double count[ORR_LF_STEPS + 1];
    double light[ORR_LF_STEPS + 1];
    double mass_density; /* the table's solar masses per pc^3 */
} orr_lf;

/* The solar neighbourhood's function, integrated (log phi linear between
 * the table's bin centres). */
void orr_lf_solar_neighbourhood(orr_lf *lf);

/* Stars per solar mass brighter than absolute magnitude m (0 brighter than
 * the table, every star fainter than it). */
double orr_lf_count_brighter(const orr_lf *lf, double m);

/* Their V light per solar mass, in solar luminosities. */
double orr_lf_light_brighter(const orr_lf *lf, double m);

/* The whole function's V light per solar mass. */
double orr_lf_light_per_mass(const orr_lf *lf);

/* The absolute magnitude at which orr_lf_count_brighter reaches count
 * (0 <= count <= the total): the inverse, linear between the steps. */
double orr_lf_magnitude_at(const orr_lf *lf, double count);

/* The same for counts that mostly grow from call to call (a particle's
 * stars, drawn brightest first): *step (start it at 0) keeps where the
 * last count fell and the search gallops on from there; the magnitude is
 * orr_lf_magnitude_at's, bit for bit, whatever *step holds. */
double orr_lf_magnitude_from(const orr_lf *lf, double count, int *step);

/* The V luminosity, in solar units, of a star of absolute magnitude m. */
double orr_lf_luminosity(double m);

/* The B-V of a star of absolute magnitude m: a giant with the probability
 * orr_lf_giant_fraction(m), else on the main sequence; u uniform in
 * [0, 1) chooses. */
double orr_lf_star_bv(double m, double u);

/* The share of giants among the stars of absolute magnitude m (our
 * approximation, docs/sky.md). */
double orr_lf_giant_fraction(double m);

#endif
