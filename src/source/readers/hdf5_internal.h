/* Shared between the HDF5 snapshot reader's files: hdf5_reader.c (finding
 * the files, checking them, streaming particles) and hdf5_header.c (the
 * header and unit entries shown by `orrery info`). */
#ifndef ORR_SOURCE_HDF5_INTERNAL_H
#define ORR_SOURCE_HDF5_INTERNAL_H

#include <hdf5.h>

#include "source/readers/hdf5_util.h"
#include "source/source.h"

/* Per-type header arrays have 2 (Gadget-4 built with NTYPES=2), 6 (Gadget,
 * AREPO, GIZMO) or 7 (SWIFT) entries; a few more are tolerated. */
#define H5R_MAX_TYPES 16

/* Room for "PartType" and any int. */
#define H5R_GROUP_NAME 24

/* The datasets of a PartTypeN group the reader knows. */
typedef enum { DS_POS, DS_VEL, DS_ID, DS_MASS, DS_H, DS_U, DS_RHO, DS_POT, DS_COUNT } h5r_dataset;

/* The dataset names of a kind: Gadget/AREPO/GIZMO spelling, then SWIFT's
 * plural where it differs (NULL when the same). */
extern const char *const h5r_dataset_names[DS_COUNT][2];

/* The name under which group has the dataset of that kind, or NULL. */
const char *h5r_dataset_name_in(hid_t group, h5r_dataset kind);

/* Adds header entries for `orrery info` from the first file: code, particle
 * counts, mass table, time, box, cosmology, unit system, and the units of the
 * datasets named in example_group[kind] (group names like "PartType0", or
 * "" when no group has that dataset). Best effort: an attribute that cannot
 * be read is left out rather than failing the open. */
void h5r_describe(orr_source_info *info, hid_t file, int ntypes,
                  const char example_group[DS_COUNT][H5R_GROUP_NAME]);

#endif
