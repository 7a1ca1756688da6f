/* Shared between the HDF5 snapshot reader's files: hdf5_reader.c (opening,
 * streaming particles), hdf5_files.c (finding the files, checking them) and
 * hdf5_header.c (the header and unit entries shown by `orrery info`),
 * hdf5_units.c (the units renders write into FITS headers). */
#ifndef ORR_SOURCE_HDF5_INTERNAL_H
#define ORR_SOURCE_HDF5_INTERNAL_H

#include <hdf5.h>

#include "source/readers/hdf5_named.h"
#include "source/readers/hdf5_util.h"
#include "source/readers/share.h"
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

/* Sets info->mass_unit and info->length_unit from the file's unit system
 * (SWIFT's Units, Gadget-4's Parameters) and the cosmological factors of
 * the datasets in example_group (hdf5_units.c); leaves them "" when the file
 * states no units or they are no FITS unit. */
void h5r_find_units(orr_source_info *info, hid_t file, const char example_group[DS_COUNT][H5R_GROUP_NAME]);

/* The extra fields the reader can load. */
enum { EX_VX, EX_VY, EX_VZ, EX_U, EX_RHO, EX_POT, EX_COUNT };

/* The reader's state (hdf5_reader.c). */
typedef struct hdf5_state {
    /* The files: numbered ones are base.0.ext .. base.(nfiles-1).ext. */
    char first[ORR_PATH_MAX];
    char base[ORR_PATH_MAX - 64];
    char ext[32];
    int numbered;
    int nfiles;
    int ntypes;
    double mass_table[H5R_MAX_TYPES];
    int64_t *npart;                 /* nfiles x ntypes: NumPart_ThisFile of each file */
    /* nfiles x ntypes: the rows of each group this process reads (all of a
     * wanted type's without a share, none of an unwanted one's). */
    orr_share share;
    unsigned type_mask;             /* types to read (bit t) */
    int present[DS_COUNT];          /* some group read has this dataset */
    int swift_h;                    /* smoothing lengths are SWIFT's (SmoothingLengths) */
    int slot[EX_COUNT];             /* chunk extra index of each extra field, or -1 */
    h5r_named named[H5R_MAX_NAMED]; /* other datasets asked for by name (hdf5_named.h) */
    int nnamed;
    /* Where reading stands. */
    int file, type;
    uint64_t row;                   /* next row within the current group */
    uint64_t emitted;               /* particles handed out so far */
    hid_t fid, gid, ds[DS_COUNT];   /* the current file, group and its datasets (-1: none) */
    char path[ORR_PATH_MAX];        /* the current file's name */
    float *scratch;                 /* 3 floats per chunk particle, for (N,3) datasets */
} hdf5_state;

/* The files of a snapshot, their headers and groups, checked before
 * anything is read (hdf5_files.c). */

/* Decides which file to open first: path itself when it exists, else the
 * first file of a multi-file snapshot whose base path names. */
orr_status h5r_resolve_first_file(hdf5_state *st, const char *path, orr_error *err);
/* The name of file i of the snapshot. */
void h5r_file_name(const hdf5_state *st, int i, char *buf, size_t size);
/* Opens one file read-only, telling apart missing files, files that are not
 * HDF5 and HDF5 files the library cannot read (truncated, corrupt). */
orr_status h5r_open_file(const char *path, hid_t *fid, const char *context, orr_error *err);
/* Opens a file's Header group, which every snapshot has. */
orr_status h5r_open_header(const char *path, hid_t fid, hid_t *header, orr_error *err);
/* The first file's header: the type count, mass table and file count. */
orr_status h5r_read_main_header(hdf5_state *st, hid_t header, orr_source *src, orr_error *err);
/* Opens and checks every file; fills st->npart and the info counts, and
 * example[kind] with a group that has the dataset of that kind. */
orr_status h5r_check_files(hdf5_state *st, hid_t first_fid, orr_source *src, char example[DS_COUNT][H5R_GROUP_NAME],
                           orr_error *err);

#endif
