/* HDF5 particle snapshots in the layout shared by Gadget-4, AREPO, GIZMO and
 * SWIFT: a Header group of attributes (NumPart_ThisFile, MassTable, Time,
 * BoxSize, NumFilesPerSnapshot, ...) and one PartTypeN group per particle
 * type holding Coordinates (N,3), and optionally Velocities, ParticleIDs,
 * Masses, SmoothingLength(s), InternalEnergy/-ies, Density/-ies and
 * Potential(s). Multi-file snapshots are named base.0.hdf5, base.1.hdf5, ...
 * See docs/format-hdf5.md. */
#ifndef ORR_SOURCE_HDF5_READER_H
#define ORR_SOURCE_HDF5_READER_H

#include <stddef.h>

#include "source/source.h"

/* Recognises the HDF5 signature \x89HDF\r\n\x1a\n at byte 0, 512, 1024 or
 * 2048 (where HDF5 puts it after a user block) of the first n bytes. */
int orr_hdf5_probe(const unsigned char *head, size_t n);

/* Opens a snapshot: path names a single file, any file of a multi-file
 * snapshot (base.K.hdf5), or the base (base.hdf5 or base, when base.0.hdf5
 * exists). Every file is checked (header, group and dataset shapes) before
 * the first particle is read; particles are then read in hyperslabs of at
 * most opt->chunk_size, file by file and type by type. Loads the extra
 * fields vx vy vz u rho pot that the file has and opt->fields asks for, and
 * only the types opt->type_mask asks for. */
orr_status orr_hdf5_source_open(const char *path, const orr_source_options *opt, orr_source **out,
                                orr_error *err);

#endif
