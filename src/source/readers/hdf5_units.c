/* The units of an HDF5 snapshot's masses and lengths as FITS unit strings
 * (info->mass_unit, info->length_unit), so renders of it carry BUNIT and
 * CUNIT when the scene names no units (docs/output.md, What a pixel holds).
 *
 * SWIFT states its unit system in the group Units ("Unit mass in cgs
 * (U_M)", "Unit length in cgs (U_L)") and each dataset's cosmological
 * factors as "h-scale exponent" and "a-scale exponent"; Gadget-4 states
 * the system in Parameters (UnitMass_in_g, UnitLength_in_cm) and the
 * factors as h_scaling and a_scaling. A quantity in physical cgs is the
 * value read times U h^eh a^ea. Only a physical unit that is a FITS unit
 * (a power of ten times solMass or g; one length symbol, since BUNIT
 * squares it) is kept: Gadget's "10^10 solMass / h" is 1.48e10 solMass
 * for h = 0.6774, which no FITS unit string says (FITS 4.0 section 4.3
 * allows only powers of ten as factors), so such files keep their units
 * unknown. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "source/readers/hdf5_internal.h"

/* How far a unit may be from a FITS unit and still be named by it. Codes'
 * constants differ from astropy's in the fourth digit (Gadget's solar mass
 * 1.989e33 g, IAU's 1.98841e33 g: 3e-4), far below any use of BUNIT. */
#define UNIT_TOLERANCE 1e-3

typedef struct named_unit {
    const char *name;
    double cgs;
} named_unit;

/* astropy's values (IAU 2015 nominal solar mass, IAU 2012 au and parsec). */
static const named_unit mass_units[] = {{"solMass", 1.988409870698051e33}, {"g", 1.0}};
static const named_unit length_units[] = {
    {"pc", 3.0856775814913673e18}, {"kpc", 3.0856775814913673e21}, {"Mpc", 3.0856775814913673e24},
    {"Gpc", 3.0856775814913673e27}, {"cm", 1.0}, {"m", 1e2}, {"km", 1e5}, {"AU", 1.495978707e13},
};

static int close_to(double value, double unit)
{
    return fabs(value / unit - 1.0) < UNIT_TOLERANCE;
}

/* value in grams as "solMass", "10**10 solMass", "10**43 g", ...; "" when
 * it is no power of ten of one of them. */
static void name_mass(double grams, char *out, size_t size)
{
    out[0] = '\0';
    if (!(grams > 0) || !isfinite(grams))
        return;
    for (size_t i = 0; i < sizeof mass_units / sizeof mass_units[0]; i++) {
        double ratio = grams / mass_units[i].cgs;
        int power = (int)lround(log10(ratio));
        if (!close_to(ratio, pow(10.0, power)))
            continue;
        if (power == 0)
            snprintf(out, size, "%s", mass_units[i].name);
        else
            snprintf(out, size, "10**%d %s", power, mass_units[i].name);
        return;
    }
}

static void name_length(double cm, char *out, size_t size)
{
    out[0] = '\0';
    for (size_t i = 0; i < sizeof length_units / sizeof length_units[0]; i++)
        if (cm > 0 && isfinite(cm) && close_to(cm, length_units[i].cgs)) {
            snprintf(out, size, "%s", length_units[i].name);
            return;
        }
}

static int read_number(hid_t loc, const char *name, double *v)
{
    int n = 0;
    int found = loc >= 0 && orr_h5_attr_numbers(loc, name, H5T_NATIVE_DOUBLE, v, 1, &n) == ORR_H5_FOUND && n == 1 &&
                isfinite(*v);
    H5Eclear2(H5E_DEFAULT);
    return found;
}

static hid_t open_quietly(hid_t loc, const char *name, int dataset)
{
    if (loc < 0 || !name || !orr_h5_has_link(loc, name))
        return -1;
    hid_t id = dataset ? H5Dopen2(loc, name, H5P_DEFAULT) : H5Gopen2(loc, name, H5P_DEFAULT);
    if (id < 0)
        H5Eclear2(H5E_DEFAULT);
    return id;
}

/* The file's unit system and what its cosmological factors need. */
typedef struct unit_system {
    double mass_g, length_cm;
    const char *h_exponent, *a_exponent; /* the datasets' attribute names */
    int comoving;                        /* Gadget-4 ComovingIntegrationOn: factors when not stated */
    int has_h, has_a;
    double h, a;
} unit_system;

static int read_system(hid_t file, unit_system *u)
{
    memset(u, 0, sizeof *u);
    hid_t header = open_quietly(file, "Header", 0);
    hid_t units = open_quietly(file, "Units", 0);
    hid_t params = open_quietly(file, "Parameters", 0);
    int found;
    if (units >= 0) {
        found = read_number(units, "Unit mass in cgs (U_M)", &u->mass_g) &&
                read_number(units, "Unit length in cgs (U_L)", &u->length_cm);
        u->h_exponent = "h-scale exponent";
        u->a_exponent = "a-scale exponent";
        u->has_a = read_number(header, "Scale-factor", &u->a);
    } else {
        found = read_number(params, "UnitMass_in_g", &u->mass_g) &&
                read_number(params, "UnitLength_in_cm", &u->length_cm);
        u->h_exponent = "h_scaling";
        u->a_exponent = "a_scaling";
        double on = 0;
        u->comoving = read_number(params, "ComovingIntegrationOn", &on) && on != 0;
        /* Gadget's Time is the scale factor in comoving runs; otherwise a
         * stated a_scaling has nothing to scale. */
        u->has_a = u->comoving ? read_number(header, "Time", &u->a) : (u->a = 1.0, 1);
    }
    u->has_h = read_number(header, "HubbleParam", &u->h) || read_number(params, "HubbleParam", &u->h);
    orr_h5_close(params);
    orr_h5_close(units);
    orr_h5_close(header);
    return found;
}

/* The physical cgs value of one unit of dataset `name` in group `group`
 * (either may be absent: then the factors a comoving Gadget run implies,
 * h^-1 and a^a_default, or none); 0 when a factor cannot be known. */
static double physical(hid_t file, const char *group, const char *name, double unit, int a_default,
                       const unit_system *u)
{
    hid_t g = group[0] ? open_quietly(file, group, 0) : -1;
    hid_t ds = open_quietly(g, name, 1);
    double eh = 0, ea = 0;
    if (!(read_number(ds, u->h_exponent, &eh) && read_number(ds, u->a_exponent, &ea))) {
        eh = u->comoving ? -1 : 0;
        ea = u->comoving ? a_default : 0;
    }
    orr_h5_close(ds);
    orr_h5_close(g);
    if ((eh != 0 && !(u->has_h && u->h > 0)) || (ea != 0 && !(u->has_a && u->a > 0)))
        return 0;
    return unit * (eh != 0 ? pow(u->h, eh) : 1.0) * (ea != 0 ? pow(u->a, ea) : 1.0);
}

void h5r_find_units(orr_source_info *info, hid_t file, const char example_group[DS_COUNT][H5R_GROUP_NAME])
{
    unit_system u;
    if (!read_system(file, &u))
        return;
    const char *pos_group = example_group[DS_POS], *mass_group = example_group[DS_MASS];
    double length = physical(file, pos_group, h5r_dataset_names[DS_POS][0], u.length_cm, 1, &u);
    /* Masses only in the MassTable: the factors of a Masses dataset. */
    double mass = physical(file, mass_group, "Masses", u.mass_g, 0, &u);
    name_mass(mass, info->mass_unit, sizeof info->mass_unit);
    name_length(length, info->length_unit, sizeof info->length_unit);
    orr_source_add_header(info, "fits.mass_unit", "%s", info->mass_unit[0] ? info->mass_unit : "(none)");
    orr_source_add_header(info, "fits.length_unit", "%s", info->length_unit[0] ? info->length_unit : "(none)");
}
