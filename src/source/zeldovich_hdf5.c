/* Writes generated initial conditions as an HDF5 snapshot in the Gadget
 * layout (the one Gadget-4 and AREPO write, which orrery's reader and most
 * analysis tools read): every particle is dark matter, type 1, of one mass
 * given in the header's MassTable. */
#include "source/zeldovich.h"

#include <hdf5.h>
#include <errno.h>
#include <stdlib.h>
#include <string.h>

#include "encode/atomic.h"

enum { NTYPES = 6 };

/* Writes n numbers as an attribute (a scalar when n == 0); 1 when it failed. */
static int put_attr(hid_t loc, const char *name, hid_t ftype, hid_t mtype, const void *v, int n)
{
    hsize_t dims[1] = {(hsize_t)n};
    hid_t space = n ? H5Screate_simple(1, dims, NULL) : H5Screate(H5S_SCALAR);
    hid_t a = space >= 0 ? H5Acreate2(loc, name, ftype, space, H5P_DEFAULT, H5P_DEFAULT) : -1;
    int bad = a < 0 || H5Awrite(a, mtype, v) < 0;
    if (a >= 0)
        H5Aclose(a);
    if (space >= 0)
        H5Sclose(space);
    return bad;
}

static int put_double(hid_t loc, const char *name, double v)
{
    return put_attr(loc, name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, &v, 0);
}

/* Object creation properties without modification times, so that the same
 * seed gives the same bytes. */
static hid_t untimed(hid_t class_id)
{
    hid_t p = H5Pcreate(class_id);
    if (p >= 0)
        H5Pset_obj_track_times(p, 0);
    return p;
}

static int write_header(hid_t file, const orr_zeldovich *z)
{
    hid_t gcpl = untimed(H5P_GROUP_CREATE);
    hid_t h = H5Gcreate2(file, "Header", H5P_DEFAULT, gcpl, H5P_DEFAULT);
    H5Pclose(gcpl);
    if (h < 0)
        return 1;
    uint32_t count[NTYPES] = {0}, high[NTYPES] = {0};
    double mass[NTYPES] = {0};
    count[1] = (uint32_t)z->n; /* grid <= 512: fewer than 2^32 particles */
    mass[1] = z->particle_mass;
    int nfiles = 1;
    int bad = put_attr(h, "NumPart_ThisFile", H5T_STD_U32LE, H5T_NATIVE_UINT32, count, NTYPES);
    bad |= put_attr(h, "NumPart_Total", H5T_STD_U32LE, H5T_NATIVE_UINT32, count, NTYPES);
    bad |= put_attr(h, "NumPart_Total_HighWord", H5T_STD_U32LE, H5T_NATIVE_UINT32, high, NTYPES);
    bad |= put_attr(h, "MassTable", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, mass, NTYPES);
    bad |= put_attr(h, "NumFilesPerSnapshot", H5T_STD_I32LE, H5T_NATIVE_INT, &nfiles, 0);
    bad |= put_double(h, "Time", z->a);
    bad |= put_double(h, "Redshift", z->redshift);
    bad |= put_double(h, "BoxSize", z->box);
    bad |= put_double(h, "Omega0", z->cosmo.omega_m);
    bad |= put_double(h, "OmegaLambda", z->cosmo.omega_lambda);
    bad |= put_double(h, "OmegaBaryon", z->cosmo.omega_b);
    bad |= put_double(h, "HubbleParam", z->cosmo.h);
    /* Gadget-2's unit attributes: lengths in Mpc/h, velocities in km/s,
     * masses in 1e10 Msun/h. */
    bad |= put_double(h, "UnitLength_in_cm", 3.085678e24);
    bad |= put_double(h, "UnitMass_in_g", 1.989e43);
    bad |= put_double(h, "UnitVelocity_in_cm_per_s", 1e5);
    H5Gclose(h);
    return bad;
}

static int write_dataset(hid_t group, const char *name, hid_t ftype, hid_t mtype, const void *data, hsize_t rows,
                         int cols)
{
    hsize_t dims[2] = {rows, (hsize_t)cols};
    hid_t space = H5Screate_simple(cols > 1 ? 2 : 1, dims, NULL);
    hid_t dcpl = untimed(H5P_DATASET_CREATE);
    hid_t ds = space >= 0 && dcpl >= 0 ? H5Dcreate2(group, name, ftype, space, H5P_DEFAULT, dcpl, H5P_DEFAULT) : -1;
    int bad = ds < 0 || H5Dwrite(ds, mtype, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) < 0;
    if (ds >= 0)
        H5Dclose(ds);
    if (dcpl >= 0)
        H5Pclose(dcpl);
    if (space >= 0)
        H5Sclose(space);
    return bad;
}

static int write_particles(hid_t file, const orr_zeldovich *z, const uint32_t *ids)
{
    hid_t gcpl = untimed(H5P_GROUP_CREATE);
    hid_t g = H5Gcreate2(file, "PartType1", H5P_DEFAULT, gcpl, H5P_DEFAULT);
    H5Pclose(gcpl);
    if (g < 0)
        return 1;
    hsize_t n = (hsize_t)z->n;
    int bad = write_dataset(g, "Coordinates", H5T_IEEE_F32LE, H5T_NATIVE_FLOAT, z->pos, n, 3);
    bad |= write_dataset(g, "Velocities", H5T_IEEE_F32LE, H5T_NATIVE_FLOAT, z->vel, n, 3);
    bad |= write_dataset(g, "ParticleIDs", H5T_STD_U32LE, H5T_NATIVE_UINT32, ids, n, 1);
    H5Gclose(g);
    return bad;
}

orr_status orr_zeldovich_write_hdf5(const orr_zeldovich *z, const char *path, orr_error *err)
{
    uint32_t *ids = orr_malloc((size_t)z->n * sizeof *ids, "particle ids", err);
    if (!ids)
        return ORR_ERR_NOMEM;
    for (int64_t i = 0; i < z->n; i++)
        ids[i] = (uint32_t)(i + 1);
    orr_atomic_file af;
    orr_status st = orr_atomic_begin(&af, path, err);
    if (st) {
        free(ids);
        return st;
    }
    /* HDF5 prints its error stack by default; the library never prints. */
    H5E_auto2_t old_fn;
    void *old_data;
    H5Eget_auto2(H5E_DEFAULT, &old_fn, &old_data);
    H5Eset_auto2(H5E_DEFAULT, NULL, NULL);
    hid_t fcpl = untimed(H5P_FILE_CREATE); /* the root group's times */
    hid_t file = H5Fcreate(af.temp_path, H5F_ACC_TRUNC, fcpl, H5P_DEFAULT);
    H5Pclose(fcpl);
    /* HDF5's messages do not give the system's reason (a full disk), so
     * errno is read right after the call that failed: the write, or the
     * close that flushes HDF5's cached metadata. */
    errno = 0;
    int bad = file < 0 || write_header(file, z) || write_particles(file, z, ids);
    int sys_errno = bad ? errno : 0;
    errno = 0;
    if (file >= 0 && H5Fclose(file) < 0) {
        bad = 1;
        sys_errno = sys_errno ? sys_errno : errno;
    }
    H5Eset_auto2(H5E_DEFAULT, old_fn, old_data);
    free(ids);
    if (bad) {
        orr_atomic_abort(&af);
        if (sys_errno)
            return orr_fail(err, ORR_ERR_IO, "%s: could not write the HDF5 snapshot: %s", path,
                            strerror(sys_errno));
        return orr_fail(err, ORR_ERR_IO, "%s: could not write the HDF5 snapshot (disk full or not writable?)",
                        path);
    }
    return orr_atomic_commit(&af, err);
}
