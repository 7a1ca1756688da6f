/* Header and unit entries for `orrery info` from an HDF5 snapshot. Gadget-4
 * keeps its unit system in Parameters (UnitLength_in_cm, ...) and the units
 * of each dataset in attributes a_scaling, h_scaling and to_cgs; SWIFT keeps
 * the unit system in Units ("Unit length in cgs (U_L)", ...) and describes
 * each dataset with an expression and a conversion factor. */
#include <stdio.h>
#include <string.h>

#include "source/hdf5_internal.h"

const char *const h5r_dataset_names[DS_COUNT][2] = {
    [DS_POS] = {"Coordinates", NULL},         [DS_VEL] = {"Velocities", NULL},
    [DS_ID] = {"ParticleIDs", NULL},          [DS_MASS] = {"Masses", NULL},
    [DS_H] = {"SmoothingLength", "SmoothingLengths"},
    [DS_U] = {"InternalEnergy", "InternalEnergies"},
    [DS_RHO] = {"Density", "Densities"},      [DS_POT] = {"Potential", "Potentials"},
};

const char *h5r_dataset_name_in(hid_t group, h5r_dataset kind)
{
    for (int i = 0; i < 2; i++) {
        const char *name = h5r_dataset_names[kind][i];
        if (name && orr_h5_has_link(group, name))
            return name;
    }
    return NULL;
}

/* Formats up to max numbers of attribute name of loc as "v0 v1 ..."; returns
 * 0 when the attribute is absent or unreadable. */
static int format_numbers(hid_t loc, const char *name, int max, char *buf, size_t size)
{
    double v[H5R_MAX_TYPES];
    int n = 0;
    if (max > H5R_MAX_TYPES)
        max = H5R_MAX_TYPES;
    if (orr_h5_attr_numbers(loc, name, H5T_NATIVE_DOUBLE, v, max, &n) != ORR_H5_FOUND) {
        H5Eclear2(H5E_DEFAULT);
        return 0;
    }
    size_t len = 0;
    buf[0] = '\0';
    for (int i = 0; i < n && len < size; i++) {
        int w = snprintf(buf + len, size - len, "%s%.10g", i ? " " : "", v[i]);
        if (w < 0)
            break;
        len += (size_t)w;
    }
    return 1;
}

/* Adds entry key from numeric attribute name of loc, when it is there. */
static int add_numbers(orr_source_info *info, const char *key, hid_t loc, const char *name, int max)
{
    char value[sizeof info->header[0].value];
    if (!format_numbers(loc, name, max, value, sizeof value))
        return 0;
    orr_source_add_header(info, key, "%s", value);
    return 1;
}

static int add_string(orr_source_info *info, const char *key, hid_t loc, const char *name)
{
    char value[sizeof info->header[0].value];
    if (orr_h5_attr_string(loc, name, value, sizeof value) != ORR_H5_FOUND) {
        H5Eclear2(H5E_DEFAULT);
        return 0;
    }
    orr_source_add_header(info, key, "%s", value);
    return 1;
}

static hid_t open_group_quietly(hid_t file, const char *name)
{
    if (!orr_h5_has_link(file, name))
        return -1;
    hid_t g = H5Gopen2(file, name, H5P_DEFAULT);
    if (g < 0)
        H5Eclear2(H5E_DEFAULT);
    return g;
}

static void describe_code(orr_source_info *info, hid_t file, hid_t header)
{
    hid_t code = open_group_quietly(file, "Code");
    if (!(code >= 0 && add_string(info, "Code", code, "Code")))
        add_string(info, "Code", header, "Code");
    if (code >= 0)
        add_string(info, "Code Version", code, "Code Version");
    orr_h5_close(code);
}

static void describe_header(orr_source_info *info, hid_t header, int ntypes)
{
    add_numbers(info, "NumFilesPerSnapshot", header, "NumFilesPerSnapshot", 1);
    add_numbers(info, "NumPart_Total", header, "NumPart_Total", ntypes);
    add_numbers(info, "NumPart_Total_HighWord", header, "NumPart_Total_HighWord", ntypes);
    add_numbers(info, "MassTable", header, "MassTable", ntypes);
    add_numbers(info, "Time", header, "Time", 1);
    add_numbers(info, "Redshift", header, "Redshift", 1);
    add_numbers(info, "Scale-factor", header, "Scale-factor", 1);
    add_numbers(info, "BoxSize", header, "BoxSize", 3);
}

/* Cosmology from Header (Gadget-2 style) or else Parameters (Gadget-4). */
static void describe_cosmology(orr_source_info *info, hid_t header, hid_t params)
{
    static const char *const names[] = {"HubbleParam", "Omega0", "OmegaLambda", "OmegaBaryon"};
    for (size_t i = 0; i < sizeof names / sizeof names[0]; i++)
        if (!add_numbers(info, names[i], header, names[i], 1) && params >= 0)
            add_numbers(info, names[i], params, names[i], 1);
}

static void describe_unit_system(orr_source_info *info, hid_t file, hid_t params)
{
    static const char *const swift[][2] = {
        {"units.length_cgs", "Unit length in cgs (U_L)"},
        {"units.mass_cgs", "Unit mass in cgs (U_M)"},
        {"units.time_cgs", "Unit time in cgs (U_t)"},
        {"units.current_cgs", "Unit current in cgs (U_I)"},
        {"units.temperature_cgs", "Unit temperature in cgs (U_T)"},
    };
    static const char *const gadget[][2] = {
        {"units.length_cgs", "UnitLength_in_cm"},
        {"units.mass_cgs", "UnitMass_in_g"},
        {"units.velocity_cgs", "UnitVelocity_in_cm_per_s"},
    };
    hid_t units = open_group_quietly(file, "Units");
    if (units >= 0)
        for (size_t i = 0; i < sizeof swift / sizeof swift[0]; i++)
            add_numbers(info, swift[i][0], units, swift[i][1], 1);
    else if (params >= 0)
        for (size_t i = 0; i < sizeof gadget / sizeof gadget[0]; i++)
            add_numbers(info, gadget[i][0], params, gadget[i][1], 1);
    orr_h5_close(units);
}

/* Collapses runs of spaces ("a U_L  [ cm ]" -> "a U_L [ cm ]"). */
static void squeeze_spaces(char *s)
{
    char *out = s;
    for (const char *p = s; *p; p++)
        if (!(*p == ' ' && (out == s || out[-1] == ' ')))
            *out++ = *p;
    while (out > s && out[-1] == ' ')
        out--;
    *out = '\0';
}

static double attr_number(hid_t loc, const char *name, int *found)
{
    double v = 0;
    int n = 0;
    *found = orr_h5_attr_numbers(loc, name, H5T_NATIVE_DOUBLE, &v, 1, &n) == ORR_H5_FOUND;
    H5Eclear2(H5E_DEFAULT);
    return v;
}

/* "a U_L [ cm ] (to cgs 1)" for SWIFT, "a^1 h^-1 (to cgs 3.085678e+21)" for
 * Gadget-4; nothing when the dataset carries neither convention. */
static void describe_dataset_units(orr_source_info *info, hid_t ds, const char *name)
{
    char expr[160];
    int has_cgs, has_a, has_h;
    if (orr_h5_attr_string(ds, "Expression for physical CGS units", expr, sizeof expr) == ORR_H5_FOUND) {
        double cgs = attr_number(ds, "Conversion factor to CGS (not including cosmological corrections)", &has_cgs);
        squeeze_spaces(expr);
        if (has_cgs)
            orr_source_add_header(info, name, "%s (to cgs %.10g)", expr, cgs);
        else
            orr_source_add_header(info, name, "%s", expr);
        return;
    }
    H5Eclear2(H5E_DEFAULT);
    double cgs = attr_number(ds, "to_cgs", &has_cgs);
    double a = attr_number(ds, "a_scaling", &has_a);
    double h = attr_number(ds, "h_scaling", &has_h);
    if (has_cgs && has_a && has_h)
        orr_source_add_header(info, name, "a^%g h^%g (to cgs %.10g)", a, h, cgs);
    else if (has_cgs)
        orr_source_add_header(info, name, "(to cgs %.10g)", cgs);
}

static void describe_datasets(orr_source_info *info, hid_t file, const char example_group[DS_COUNT][H5R_GROUP_NAME])
{
    for (int k = 0; k < DS_COUNT; k++) {
        if (k == DS_ID || !example_group[k][0])
            continue;
        hid_t g = open_group_quietly(file, example_group[k]);
        const char *name = g >= 0 ? h5r_dataset_name_in(g, (h5r_dataset)k) : NULL;
        hid_t ds = name ? H5Dopen2(g, name, H5P_DEFAULT) : -1;
        if (ds >= 0)
            describe_dataset_units(info, ds, name);
        H5Eclear2(H5E_DEFAULT);
        orr_h5_close(ds);
        orr_h5_close(g);
    }
}

void h5r_describe(orr_source_info *info, hid_t file, int ntypes, const char example_group[DS_COUNT][H5R_GROUP_NAME])
{
    hid_t header = open_group_quietly(file, "Header");
    hid_t params = open_group_quietly(file, "Parameters");
    if (header >= 0) {
        describe_code(info, file, header);
        describe_header(info, header, ntypes);
        describe_cosmology(info, header, params);
    }
    describe_unit_system(info, file, params);
    describe_datasets(info, file, example_group);
    orr_h5_close(params);
    orr_h5_close(header);
}
