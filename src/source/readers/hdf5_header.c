/* Header and unit entries for `orrery info` from an HDF5 snapshot. Gadget-4
 * keeps its unit system in Parameters (UnitLength_in_cm, ...) and the units
 * of each dataset in attributes a_scaling, h_scaling and to_cgs; SWIFT keeps
 * the unit system in Units ("Unit length in cgs (U_L)", ...) and describes
 * each dataset with an expression and a conversion factor. */
#include <stdio.h>
#include <string.h>

#include "source/readers/hdf5_internal.h"

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
 * Gadget-4, into buf; 0 (buf "") when the dataset carries neither. */
static int format_dataset_units(hid_t ds, char *buf, size_t size)
{
    char expr[160];
    int has_cgs, has_a, has_h;
    buf[0] = '\0';
    if (orr_h5_attr_string(ds, "Expression for physical CGS units", expr, sizeof expr) == ORR_H5_FOUND) {
        double cgs = attr_number(ds, "Conversion factor to CGS (not including cosmological corrections)", &has_cgs);
        squeeze_spaces(expr);
        if (has_cgs)
            snprintf(buf, size, "%s (to cgs %.10g)", expr, cgs);
        else
            snprintf(buf, size, "%s", expr);
        return 1;
    }
    H5Eclear2(H5E_DEFAULT);
    double cgs = attr_number(ds, "to_cgs", &has_cgs);
    double a = attr_number(ds, "a_scaling", &has_a);
    double h = attr_number(ds, "h_scaling", &has_h);
    if (has_cgs && has_a && has_h)
        snprintf(buf, size, "a^%g h^%g (to cgs %.10g)", a, h, cgs);
    else if (has_cgs)
        snprintf(buf, size, "(to cgs %.10g)", cgs);
    return buf[0] != '\0';
}

static void describe_dataset_units(orr_source_info *info, hid_t ds, const char *name)
{
    char units[sizeof info->header[0].value];
    if (format_dataset_units(ds, units, sizeof units))
        orr_source_add_header(info, name, "%s", units);
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

/* ---- every other dataset: a named field (format-hdf5.md) ---- */

#define MAX_LISTED 64

typedef struct dataset_list {
    int n;
    char name[MAX_LISTED][48];
} dataset_list;

static int is_standard_dataset(const char *name)
{
    for (int k = 0; k < DS_COUNT; k++)
        for (int i = 0; i < 2; i++)
            if (h5r_dataset_names[k][i] && strcmp(name, h5r_dataset_names[k][i]) == 0)
                return 1;
    return 0;
}

/* The names of group g's links that are not standard datasets, once each
 * (H5Gget_info and H5Lget_name_by_idx: in HDF5 1.10 and later alike). */
static void collect_names(hid_t g, dataset_list *list)
{
    H5G_info_t gi;
    if (H5Gget_info(g, &gi) < 0)
        return;
    for (hsize_t i = 0; i < gi.nlinks && list->n < MAX_LISTED; i++) {
        char name[48];
        ssize_t len = H5Lget_name_by_idx(g, ".", H5_INDEX_NAME, H5_ITER_INC, i, name, sizeof name, H5P_DEFAULT);
        if (len < 0 || (size_t)len >= sizeof name || is_standard_dataset(name))
            continue;
        int dup = 0;
        for (int k = 0; k < list->n; k++)
            dup |= strcmp(list->name[k], name) == 0;
        if (!dup)
            snprintf(list->name[list->n++], sizeof list->name[0], "%s", name);
    }
}

/* One entry for a dataset usable as a named field: its group, shape, the
 * field names it gives and its units. Not numbers, or more than 2-D: none. */
static void describe_named(orr_source_info *info, hid_t group, const char *group_name, const char *name)
{
    hid_t ds = H5Dopen2(group, name, H5P_DEFAULT);
    hsize_t dims[ORR_H5_MAX_RANK];
    H5T_class_t cls = H5T_NO_CLASS;
    int rank = ds >= 0 ? orr_h5_dataset_shape(ds, dims, &cls) : -1;
    char units[160] = "";
    if (ds >= 0)
        format_dataset_units(ds, units, sizeof units);
    H5Eclear2(H5E_DEFAULT);
    orr_h5_close(ds);
    if ((cls != H5T_INTEGER && cls != H5T_FLOAT) || rank < 1 || rank > 2)
        return;
    char shape[160];
    /* A field name holds at most ORR_FIELD_NAME_MAX - 1 characters, with
     * "[k]" for a column: longer datasets are listed but cannot be fields. */
    size_t room = ORR_FIELD_NAME_MAX - 1 - (rank == 2 ? 2 + (dims[1] > 10 ? 2 : 1) : 0);
    if (strlen(name) > room)
        snprintf(shape, sizeof shape, "(%llu%s): name too long for a field", (unsigned long long)dims[0],
                 rank == 2 ? ", ..." : "");
    else if (rank == 1)
        snprintf(shape, sizeof shape, "(%llu): field %s", (unsigned long long)dims[0], name);
    else
        snprintf(shape, sizeof shape, "(%llu, %llu): fields %s[0..%llu]", (unsigned long long)dims[0],
                 (unsigned long long)dims[1], name, (unsigned long long)dims[1] - 1);
    orr_source_add_header(info, name, "%s %s%s%s", group_name, shape, units[0] ? "; " : "", units);
}

/* Every numeric dataset of the particle groups other than the standard
 * ones, once (in the first group holding it), with its units. */
static void describe_named_datasets(orr_source_info *info, hid_t file, int ntypes)
{
    for (int t = 0; t < ntypes; t++) {
        char group_name[24];
        snprintf(group_name, sizeof group_name, "PartType%d", t);
        hid_t g = open_group_quietly(file, group_name);
        if (g < 0)
            continue;
        dataset_list list = {0}, seen_before = {0};
        for (int k = 0; k < info->nheader; k++)
            if (seen_before.n < MAX_LISTED)
                snprintf(seen_before.name[seen_before.n++], sizeof seen_before.name[0], "%s", info->header[k].key);
        collect_names(g, &list);
        H5Eclear2(H5E_DEFAULT);
        for (int i = 0; i < list.n; i++) {
            int listed = 0;
            for (int k = 0; k < seen_before.n; k++)
                listed |= strcmp(seen_before.name[k], list.name[i]) == 0;
            if (!listed)
                describe_named(info, g, group_name, list.name[i]);
        }
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
    describe_named_datasets(info, file, ntypes);
    orr_h5_close(params);
    orr_h5_close(header);
}
