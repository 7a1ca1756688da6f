/* Generated initial conditions (zeldovich.h) written as a snapshot file. */
#ifndef ORR_SOURCE_ZELDOVICH_HDF5_H
#define ORR_SOURCE_ZELDOVICH_HDF5_H

#include "core/error.h"
#include "source/models/zeldovich.h"

/* Writes the particles as an HDF5 snapshot in the Gadget layout (Header
 * with BoxSize, MassTable, Time, Redshift, Omega0, OmegaLambda,
 * HubbleParam; PartType1 with Coordinates, Velocities, ParticleIDs), to a
 * temporary name renamed into place when complete. */
orr_status orr_zeldovich_write_hdf5(const orr_zeldovich *z, const char *path, orr_error *err);

#endif
