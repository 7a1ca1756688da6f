/* Writes generated initial conditions as an HDF5 snapshot in the Gadget
 * layout (the one Gadget-4 and AREPO write, which orrery's reader and most
 * analysis tools read): every particle is dark matter, type 1, of one mass
 * given in the header's MassTable. */
#include "source/writers/zeldovich_hdf5.h"

#include <stdlib.h>

#include "source/writers/hdf5_write.h"

enum { NTYPES = 6 };

static int write_header(hid_t file, const orr_zeldovich *z)
{
    hid_t h = orr_h5w_group(file, "Header");
    if (h < 0)
        return 1;
    uint32_t count[NTYPES] = {0}, high[NTYPES] = {0};
    double mass[NTYPES] = {0};
    count[1] = (uint32_t)z->n; /* grid <= 512: fewer than 2^32 particles */
    mass[1] = z->particle_mass;
    int nfiles = 1;
    int bad = orr_h5w_attr(h, "NumPart_ThisFile", H5T_STD_U32LE, H5T_NATIVE_UINT32, count, NTYPES);
    bad |= orr_h5w_attr(h, "NumPart_Total", H5T_STD_U32LE, H5T_NATIVE_UINT32, count, NTYPES);
    bad |= orr_h5w_attr(h, "NumPart_Total_HighWord", H5T_STD_U32LE, H5T_NATIVE_UINT32, high, NTYPES);
    bad |= orr_h5w_attr(h, "MassTable", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, mass, NTYPES);
    bad |= orr_h5w_attr(h, "NumFilesPerSnapshot", H5T_STD_I32LE, H5T_NATIVE_INT, &nfiles, 0);
    bad |= orr_h5w_double(h, "Time", z->a);
    bad |= orr_h5w_double(h, "Redshift", z->redshift);
    bad |= orr_h5w_double(h, "BoxSize", z->box);
    bad |= orr_h5w_double(h, "Omega0", z->cosmo.omega_m);
    bad |= orr_h5w_double(h, "OmegaLambda", z->cosmo.omega_lambda);
    bad |= orr_h5w_double(h, "OmegaBaryon", z->cosmo.omega_b);
    bad |= orr_h5w_double(h, "HubbleParam", z->cosmo.h);
    /* Gadget-2's unit attributes: lengths in Mpc/h, velocities in km/s,
     * masses in 1e10 Msun/h. */
    bad |= orr_h5w_double(h, "UnitLength_in_cm", 3.085678e24);
    bad |= orr_h5w_double(h, "UnitMass_in_g", 1.989e43);
    bad |= orr_h5w_double(h, "UnitVelocity_in_cm_per_s", 1e5);
    return orr_h5w_close_group(h, bad);
}

static int write_particles(hid_t file, const orr_zeldovich *z, const uint32_t *ids)
{
    hid_t g = orr_h5w_group(file, "PartType1");
    if (g < 0)
        return 1;
    hsize_t n = (hsize_t)z->n;
    int bad = orr_h5w_dataset(g, "Coordinates", H5T_IEEE_F32LE, H5T_NATIVE_FLOAT, z->pos, n, 3);
    bad |= orr_h5w_dataset(g, "Velocities", H5T_IEEE_F32LE, H5T_NATIVE_FLOAT, z->vel, n, 3);
    bad |= orr_h5w_dataset(g, "ParticleIDs", H5T_STD_U32LE, H5T_NATIVE_UINT32, ids, n, 1);
    return orr_h5w_close_group(g, bad);
}

typedef struct zel_write {
    const orr_zeldovich *z;
    const uint32_t *ids;
} zel_write;

static int write_body(hid_t file, void *ctx)
{
    const zel_write *w = ctx;
    return write_header(file, w->z) || write_particles(file, w->z, w->ids);
}

orr_status orr_zeldovich_write_hdf5(const orr_zeldovich *z, const char *path, orr_error *err)
{
    uint32_t *ids = orr_malloc((size_t)z->n * sizeof *ids, "particle ids", err);
    if (!ids)
        return ORR_ERR_NOMEM;
    for (int64_t i = 0; i < z->n; i++)
        ids[i] = (uint32_t)(i + 1);
    zel_write w = {z, ids};
    orr_status st = orr_h5w_write_file(path, write_body, &w, err);
    free(ids);
    return st;
}
