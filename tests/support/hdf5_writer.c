#include "hdf5_writer.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Writes n numbers as an attribute: a scalar when n == 1 and the style is
 * Gadget's, otherwise a 1-D array (SWIFT writes even single values so). */
static int attr_numbers(hid_t loc, const char *name, hid_t ftype, hid_t mtype, const void *v, int n, int array)
{
    hsize_t dims[1] = {(hsize_t)n};
    hid_t space = (n == 1 && !array) ? H5Screate(H5S_SCALAR) : H5Screate_simple(1, dims, NULL);
    hid_t a = H5Acreate2(loc, name, ftype, space, H5P_DEFAULT, H5P_DEFAULT);
    int ok = a >= 0 && H5Awrite(a, mtype, v) >= 0;
    if (a >= 0)
        H5Aclose(a);
    H5Sclose(space);
    return ok ? 0 : -1;
}

static int attr_double(hid_t loc, const char *name, double v, int array)
{
    return attr_numbers(loc, name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, &v, 1, array);
}

static int attr_string(hid_t loc, const char *name, const char *s)
{
    hid_t type = H5Tcopy(H5T_C_S1);
    H5Tset_size(type, strlen(s) ? strlen(s) : 1);
    hid_t space = H5Screate(H5S_SCALAR);
    hid_t a = H5Acreate2(loc, name, type, space, H5P_DEFAULT, H5P_DEFAULT);
    int ok = a >= 0 && H5Awrite(a, type, s) >= 0;
    if (a >= 0)
        H5Aclose(a);
    H5Sclose(space);
    H5Tclose(type);
    return ok ? 0 : -1;
}

static int write_header(hid_t file, const h5w_snapshot *s)
{
    int swift = s->style == H5W_SWIFT;
    uint64_t this_file[H5W_MAX_TYPES], total[H5W_MAX_TYPES];
    uint32_t low[H5W_MAX_TYPES], high[H5W_MAX_TYPES];
    int any_total = 0;
    for (int t = 0; t < s->ntypes; t++)
        any_total |= s->total[t] != 0;
    for (int t = 0; t < s->ntypes; t++) {
        this_file[t] = s->part[t].n;
        total[t] = any_total ? s->total[t] : this_file[t];
        low[t] = (uint32_t)total[t];
        high[t] = (uint32_t)(total[t] >> 32);
    }
    int nfiles = s->nfiles ? s->nfiles : 1;
    hid_t h = H5Gcreate2(file, "Header", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    int n = s->ntypes, bad = h < 0;
    /* Gadget-4 writes NumPart_ThisFile as u32 and NumPart_Total as u64; SWIFT
     * the other way round (see shared/data/README.md). */
    bad |= attr_numbers(h, "NumPart_ThisFile", swift ? H5T_STD_U64LE : H5T_STD_U32LE, H5T_NATIVE_UINT64, this_file,
                        n, 1);
    if (swift || n == 6) {
        bad |= attr_numbers(h, "NumPart_Total", H5T_STD_U32LE, H5T_NATIVE_UINT32, low, n, 1);
        bad |= attr_numbers(h, "NumPart_Total_HighWord", H5T_STD_U32LE, H5T_NATIVE_UINT32, high, n, 1);
    } else {
        bad |= attr_numbers(h, "NumPart_Total", H5T_STD_U64LE, H5T_NATIVE_UINT64, total, n, 1);
    }
    bad |= attr_numbers(h, "MassTable", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, s->mass_table, n, 1);
    bad |= attr_double(h, "Time", s->time, swift);
    bad |= attr_double(h, "Redshift", s->redshift, swift);
    bad |= attr_numbers(h, "NumFilesPerSnapshot", H5T_STD_I32LE, H5T_NATIVE_INT, &nfiles, 1, swift);
    if (swift) {
        double box[3] = {s->box, s->box, s->box};
        double a = s->time;
        bad |= attr_numbers(h, "BoxSize", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, box, 3, 1);
        bad |= attr_double(h, "Scale-factor", a, 1);
        bad |= attr_numbers(h, "NumPartTypes", H5T_STD_I32LE, H5T_NATIVE_INT, &n, 1, 1);
        bad |= attr_string(h, "Code", "SWIFT");
    } else {
        bad |= attr_double(h, "BoxSize", s->box, 0);
    }
    if (h >= 0)
        H5Gclose(h);
    return bad ? -1 : 0;
}

/* SWIFT's Code and Units groups, or Gadget-4's Parameters units. */
static int write_unit_groups(hid_t file, const h5w_snapshot *s)
{
    int bad = 0;
    if (s->style == H5W_SWIFT) {
        static const char *const units[] = {"Unit length in cgs (U_L)", "Unit mass in cgs (U_M)",
                                            "Unit time in cgs (U_t)", "Unit current in cgs (U_I)",
                                            "Unit temperature in cgs (U_T)"};
        hid_t code = H5Gcreate2(file, "Code", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
        bad |= code < 0 || attr_string(code, "Code", "SWIFT") || attr_string(code, "Code Version", "1.0.0");
        hid_t u = H5Gcreate2(file, "Units", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
        for (size_t i = 0; i < sizeof units / sizeof units[0]; i++)
            bad |= attr_double(u, units[i], 1.0, 1);
        H5Gclose(u);
        H5Gclose(code);
    } else if (s->gadget4_units) {
        hid_t p = H5Gcreate2(file, "Parameters", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
        bad |= attr_double(p, "UnitLength_in_cm", 3.085678e21, 0);
        bad |= attr_double(p, "UnitMass_in_g", 1.989e43, 0);
        bad |= attr_double(p, "UnitVelocity_in_cm_per_s", 1e5, 0);
        bad |= attr_double(p, "HubbleParam", 0.7, 0);
        H5Gclose(p);
    }
    return bad ? -1 : 0;
}

/* Unit attributes of a dataset in the style's convention. */
static int dataset_units(hid_t ds, const h5w_snapshot *s, const char *expression, double a_exp, double to_cgs)
{
    if (s->style == H5W_SWIFT)
        return attr_string(ds, "Expression for physical CGS units", expression) |
               attr_double(ds, "Conversion factor to CGS (not including cosmological corrections)", 1.0, 1) |
               attr_double(ds, "a-scale exponent", a_exp, 1) | attr_double(ds, "h-scale exponent", 0.0, 1);
    if (s->gadget4_units)
        return attr_double(ds, "a_scaling", a_exp, 0) | attr_double(ds, "h_scaling", -1.0, 0) |
               attr_double(ds, "to_cgs", to_cgs, 0);
    return 0;
}

/* A transfer property list whose type-conversion buffer is 64 KiB rather
 * than HDF5's default 1 MiB, which HDF5 allocates and clears on every
 * converting write: small writes (the fuzz targets make many) go faster. */
static hid_t small_buffer_dxpl(void)
{
    hid_t dxpl = H5Pcreate(H5P_DATASET_XFER);
    if (dxpl >= 0)
        H5Pset_buffer(dxpl, 64 * 1024, NULL, NULL);
    return dxpl;
}

static int write_dataset(hid_t group, const char *name, hid_t ftype, hid_t mtype, size_t n, int cols,
                         const void *data, const h5w_snapshot *s, const char *expression, double a_exp,
                         double to_cgs)
{
    hsize_t dims[2] = {n, (hsize_t)cols};
    hid_t space = H5Screate_simple(cols ? 2 : 1, dims, NULL);
    hid_t ds = H5Dcreate2(group, name, ftype, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    hid_t dxpl = small_buffer_dxpl();
    int ok = ds >= 0 && H5Dwrite(ds, mtype, H5S_ALL, H5S_ALL, dxpl, data) >= 0 &&
             dataset_units(ds, s, expression, a_exp, to_cgs) == 0;
    if (ds >= 0)
        H5Dclose(ds);
    H5Pclose(dxpl);
    H5Sclose(space);
    return ok ? 0 : -1;
}

static int write_part(hid_t file, int t, const h5w_snapshot *s)
{
    const h5w_part *p = &s->part[t];
    if (p->n == 0)
        return 0;
    int swift = s->style == H5W_SWIFT;
    hid_t pos_type = s->pos_type ? s->pos_type : H5T_IEEE_F32LE;
    hid_t id_type = s->id_type ? s->id_type : H5T_STD_U32LE;
    char name[32];
    snprintf(name, sizeof name, "PartType%d", t);
    hid_t g = H5Gcreate2(file, name, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    if (g < 0)
        return -1;
    const hid_t f32 = H5T_IEEE_F32LE, dbl = H5T_NATIVE_DOUBLE;
    int bad = 0;
    if (p->pos)
        bad |= write_dataset(g, "Coordinates", pos_type, dbl, p->n, 3, p->pos, s, "a U_L  [ cm ]", 1, 3.085678e21);
    if (p->vel)
        bad |= write_dataset(g, "Velocities", pos_type, dbl, p->vel ? p->n : 0, 3, p->vel, s, "U_L U_t^-1  [ cm s^-1 ]",
                             0, 1e5);
    if (p->id)
        bad |= write_dataset(g, "ParticleIDs", id_type, H5T_NATIVE_UINT64, p->n, 0, p->id, s, "[ - ]", 0, 1);
    if (p->mass)
        bad |= write_dataset(g, "Masses", f32, dbl, p->n, 0, p->mass, s, "U_M  [ g ]", 0, 1.989e43);
    if (p->h)
        bad |= write_dataset(g, swift ? "SmoothingLengths" : "SmoothingLength", f32, dbl, p->n, 0, p->h, s,
                             "a U_L  [ cm ]", 1, 3.085678e21);
    if (p->u)
        bad |= write_dataset(g, swift ? "InternalEnergies" : "InternalEnergy", f32, dbl, p->n, 0, p->u, s,
                             "U_L^2 U_t^-2  [ cm^2 s^-2 ]", -2, 1e10);
    if (p->rho)
        bad |= write_dataset(g, swift ? "Densities" : "Density", f32, dbl, p->n, 0, p->rho, s,
                             "a^-3 U_M U_L^-3  [ g cm^-3 ]", -3, 6.769911178294544e-22);
    if (p->pot)
        bad |= write_dataset(g, swift ? "Potentials" : "Potential", f32, dbl, p->n, 0, p->pot, s,
                             "U_L^2 U_t^-2  [ cm^2 s^-2 ]", -1, 1e10);
    H5Gclose(g);
    return bad ? -1 : 0;
}

int h5w_write_open(const char *path, const h5w_snapshot *s, hid_t *file)
{
    *file = -1;
    if (s->ntypes < 1 || s->ntypes > H5W_MAX_TYPES)
        return -1;
    *file = H5Fcreate(path, H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    if (*file < 0)
        return -1;
    int bad = write_header(*file, s) | write_unit_groups(*file, s);
    for (int t = 0; t < s->ntypes; t++)
        bad |= write_part(*file, t, s);
    return bad ? -1 : 0;
}

int h5w_write(const char *path, const h5w_snapshot *s)
{
    hid_t file;
    int r = h5w_write_open(path, s, &file);
    if (file >= 0)
        H5Fclose(file);
    return r;
}

int h5w_delete_in(hid_t file, const char *object)
{
    return H5Ldelete(file, object, H5P_DEFAULT) >= 0 ? 0 : -1;
}

int h5w_delete(const char *path, const char *object)
{
    hid_t file = H5Fopen(path, H5F_ACC_RDWR, H5P_DEFAULT);
    if (file < 0)
        return -1;
    int r = h5w_delete_in(file, object);
    H5Fclose(file);
    return r;
}

int h5w_replace_dataset(const char *path, const char *object, size_t rows, size_t cols, double value)
{
    hid_t file = H5Fopen(path, H5F_ACC_RDWR, H5P_DEFAULT);
    if (file < 0)
        return -1;
    if (H5Lexists(file, object, H5P_DEFAULT) > 0)
        H5Ldelete(file, object, H5P_DEFAULT);
    size_t count = rows * (cols ? cols : 1);
    float *data = malloc((count ? count : 1) * sizeof *data);
    for (size_t i = 0; i < count; i++)
        data[i] = (float)value;
    hsize_t dims[2] = {rows, cols};
    hid_t space = H5Screate_simple(cols ? 2 : 1, dims, NULL);
    hid_t ds = H5Dcreate2(file, object, H5T_IEEE_F32LE, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    int ok = ds >= 0 && H5Dwrite(ds, H5T_NATIVE_FLOAT, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) >= 0;
    if (ds >= 0)
        H5Dclose(ds);
    H5Sclose(space);
    H5Fclose(file);
    free(data);
    return ok ? 0 : -1;
}

int h5w_set_int64_attr(const char *path, const char *group, const char *name, const int64_t *values, int n)
{
    hid_t file = H5Fopen(path, H5F_ACC_RDWR, H5P_DEFAULT);
    if (file < 0)
        return -1;
    hid_t g = H5Gopen2(file, group, H5P_DEFAULT);
    if (g >= 0 && H5Aexists(g, name) > 0)
        H5Adelete(g, name);
    int ok = g >= 0 && attr_numbers(g, name, H5T_STD_I64LE, H5T_NATIVE_INT64, values, n, 1) == 0;
    if (g >= 0)
        H5Gclose(g);
    H5Fclose(file);
    return ok ? 0 : -1;
}

int h5w_write_groups(const char *path, const char *const *groups)
{
    hid_t file = H5Fcreate(path, H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    if (file < 0)
        return -1;
    int bad = 0;
    for (int i = 0; groups[i]; i++) {
        hid_t g = H5Gcreate2(file, groups[i], H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
        bad |= g < 0;
        if (g >= 0)
            H5Gclose(g);
    }
    H5Fclose(file);
    return bad ? -1 : 0;
}

/* Opens group of a file open for writing and removes its attribute name
 * if it has one. */
static hid_t open_for_attr(hid_t file, const char *group, const char *name)
{
    hid_t g = H5Oopen(file, group, H5P_DEFAULT);
    if (g >= 0 && H5Aexists(g, name) > 0)
        H5Adelete(g, name);
    return g;
}

int h5w_set_attr(hid_t file, const char *group, const char *name, hid_t type, int rank, const double *values, int n)
{
    hid_t g = open_for_attr(file, group, name);
    hsize_t dims[1] = {(hsize_t)(n > 0 ? n : 0)};
    hid_t space = rank < 0 ? H5Screate(H5S_NULL) : rank == 0 ? H5Screate(H5S_SCALAR) : H5Screate_simple(1, dims, NULL);
    hid_t a = g >= 0 ? H5Acreate2(g, name, type, space, H5P_DEFAULT, H5P_DEFAULT) : -1;
    int ok = a >= 0 && (rank < 0 || (rank == 0 ? n >= 1 : n >= 0));
    if (ok && rank >= 0 && n > 0)
        ok = H5Awrite(a, H5T_NATIVE_DOUBLE, values) >= 0;
    if (a >= 0)
        H5Aclose(a);
    H5Sclose(space);
    if (g >= 0)
        H5Oclose(g);
    return ok ? 0 : -1;
}

int h5w_set_string_attr(hid_t file, const char *group, const char *name, const char *value, int variable)
{
    hid_t g = open_for_attr(file, group, name);
    int ok = g >= 0;
    if (ok && variable) {
        hid_t type = H5Tcopy(H5T_C_S1);
        H5Tset_size(type, H5T_VARIABLE);
        hid_t space = H5Screate(H5S_SCALAR);
        hid_t a = H5Acreate2(g, name, type, space, H5P_DEFAULT, H5P_DEFAULT);
        ok = a >= 0 && H5Awrite(a, type, &value) >= 0;
        if (a >= 0)
            H5Aclose(a);
        H5Sclose(space);
        H5Tclose(type);
    } else if (ok) {
        ok = attr_string(g, name, value) == 0;
    }
    if (g >= 0)
        H5Oclose(g);
    return ok ? 0 : -1;
}

int h5w_replace_dataset_spec(hid_t file, const char *object, const h5w_dataset_spec *spec)
{
    if (spec->rank < -1 || spec->rank > 3)
        return -1;
    if (H5Lexists(file, object, H5P_DEFAULT) > 0)
        H5Ldelete(file, object, H5P_DEFAULT);
    hid_t type = spec->type ? spec->type : H5T_IEEE_F32LE;
    int rank = spec->rank;
    int chunked = rank > 0 && spec->chunk_rows;
    hsize_t chunk[3], maxdims[3] = {H5S_UNLIMITED, H5S_UNLIMITED, H5S_UNLIMITED};
    hid_t space = rank < 0    ? H5Screate(H5S_NULL)
                  : rank == 0 ? H5Screate(H5S_SCALAR)
                              : H5Screate_simple(rank, spec->dims, chunked ? maxdims : NULL);
    hid_t dcpl = H5Pcreate(H5P_DATASET_CREATE);
    if (chunked) {
        for (int i = 0; i < rank; i++)
            chunk[i] = spec->dims[i] ? spec->dims[i] : 1;
        chunk[0] = spec->chunk_rows;
        H5Pset_chunk(dcpl, rank, chunk);
    }
    hid_t ds = H5Dcreate2(file, object, type, space, H5P_DEFAULT, dcpl, H5P_DEFAULT);
    int ok = ds >= 0;
    /* Elements to write: the first write_rows rows, or the scalar. */
    hsize_t count[3] = {0, 1, 1};
    size_t per_row = 1;
    for (int i = 1; i < rank; i++) {
        count[i] = spec->dims[i];
        per_row *= (size_t)spec->dims[i];
    }
    size_t rows = rank > 0 ? (size_t)(spec->write_rows < spec->dims[0] ? spec->write_rows : spec->dims[0]) : 1;
    size_t total = rank < 0 ? 0 : rows * per_row;
    H5T_class_t cls = H5Tget_class(type);
    if (ok && total > 0 && (cls == H5T_INTEGER || cls == H5T_FLOAT)) {
        double *data = malloc(total * sizeof *data);
        for (size_t i = 0; data && i < total; i++)
            data[i] = spec->values && spec->nvalues ? spec->values[i % spec->nvalues] : 0.0;
        hid_t fspace = H5Dget_space(ds);
        hid_t mspace = -1, dxpl = small_buffer_dxpl();
        if (rank > 0) {
            hsize_t start[3] = {0, 0, 0};
            count[0] = rows;
            mspace = H5Screate_simple(rank, count, NULL);
            ok = H5Sselect_hyperslab(fspace, H5S_SELECT_SET, start, NULL, count, NULL) >= 0;
        } else {
            mspace = H5Screate(H5S_SCALAR);
        }
        ok = ok && data && H5Dwrite(ds, H5T_NATIVE_DOUBLE, mspace, fspace, dxpl, data) >= 0;
        H5Pclose(dxpl);
        H5Sclose(mspace);
        H5Sclose(fspace);
        free(data);
    }
    if (ds >= 0)
        H5Dclose(ds);
    H5Pclose(dcpl);
    H5Sclose(space);
    return ok ? 0 : -1;
}

int h5w_delete_attr(hid_t file, const char *group, const char *name)
{
    hid_t g = H5Oopen(file, group, H5P_DEFAULT);
    int ok = g >= 0 && H5Adelete(g, name) >= 0;
    if (g >= 0)
        H5Oclose(g);
    return ok ? 0 : -1;
}

int h5w_add_group(hid_t file, const char *object)
{
    hid_t g = H5Gcreate2(file, object, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    if (g >= 0)
        H5Gclose(g);
    return g >= 0 ? 0 : -1;
}

int h5w_add_link(hid_t file, const char *name, const char *target, int hard)
{
    if (H5Lexists(file, name, H5P_DEFAULT) > 0)
        H5Ldelete(file, name, H5P_DEFAULT);
    herr_t r = hard ? H5Lcreate_hard(file, target, file, name, H5P_DEFAULT, H5P_DEFAULT)
                    : H5Lcreate_soft(target, file, name, H5P_DEFAULT, H5P_DEFAULT);
    return r >= 0 ? 0 : -1;
}
