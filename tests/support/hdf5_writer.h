/* A test-only writer of HDF5 snapshots in the Gadget (Gadget-4, AREPO,
 * GIZMO) and SWIFT layouts, with the HDF5 C API, for the reader's round-trip
 * tests and the fuzz corpus; plus small editors that spoil a written file
 * (delete an object, replace a dataset, overwrite an attribute) for the
 * bad-input tests. Every function returns 0 on success, -1 on failure. */
#ifndef ORR_TEST_HDF5_WRITER_H
#define ORR_TEST_HDF5_WRITER_H

#include <hdf5.h>
#include <stddef.h>
#include <stdint.h>

#define H5W_MAX_TYPES 7

typedef enum {
    H5W_GADGET, /* scalar attributes, scalar BoxSize, SmoothingLength, Density, ... */
    H5W_SWIFT   /* 1-element array attributes, 3-vector BoxSize, SmoothingLengths,
                 * Densities, ..., Code and Units groups, unit attributes per dataset */
} h5w_style;

/* The particles of one PartTypeN group; any array may be NULL (the dataset
 * is then not written; a group without Coordinates is for the bad-input
 * tests). Values are written converted to the file types of the snapshot. A
 * group with n == 0 is not written at all. */
typedef struct h5w_part {
    size_t n;
    const double *pos; /* 3n: x0 y0 z0 x1 ... */
    const double *vel; /* 3n */
    const uint64_t *id;
    const double *mass, *h, *u, *rho, *pot;
} h5w_part;

typedef struct h5w_snapshot {
    h5w_style style;
    int ntypes;      /* entries of the per-type header arrays: 2, 6 or 7 */
    hid_t pos_type;  /* file type of Coordinates and Velocities (0: H5T_IEEE_F32LE) */
    hid_t id_type;   /* file type of ParticleIDs (0: H5T_STD_U32LE) */
    double mass_table[H5W_MAX_TYPES];
    double time, redshift, box;
    int nfiles;                    /* NumFilesPerSnapshot (0: 1) */
    uint64_t total[H5W_MAX_TYPES]; /* NumPart_Total (all 0: this file's counts) */
    int gadget4_units;             /* Gadget style: Parameters units and a_scaling/h_scaling/to_cgs */
    h5w_part part[H5W_MAX_TYPES];
} h5w_snapshot;

int h5w_write(const char *path, const h5w_snapshot *s);

/* Editors of an existing file; object paths like "PartType0/Masses". */
int h5w_delete(const char *path, const char *object);
/* Replaces (or adds) a float32 dataset of rows x cols (cols 0: 1-D) filled
 * with value. */
int h5w_replace_dataset(const char *path, const char *object, size_t rows, size_t cols, double value);
/* Writes (replacing) a 1-D int64 attribute of n values on group. */
int h5w_set_int64_attr(const char *path, const char *group, const char *name, const int64_t *values, int n);
/* Writes a file with only the named empty groups (a NULL-terminated list). */
int h5w_write_groups(const char *path, const char *const *groups);

/* The same as h5w_write, but leaves the file open (in *file, -1 when it
 * could not be created) for the editors below, which the fuzz target applies
 * without reopening the file each time; close it with H5Fclose. */
int h5w_write_open(const char *path, const h5w_snapshot *s, hid_t *file);

/* Editors of a file open for writing (from h5w_write_open, or H5Fopen with
 * H5F_ACC_RDWR); object and group paths like "PartType0/Masses", "/" for the
 * root group. */
int h5w_delete_in(hid_t file, const char *object);

/* A dataset of any type and shape, for h5w_replace_dataset_spec. */
typedef struct h5w_dataset_spec {
    hid_t type;           /* file type (0: H5T_IEEE_F32LE); a non-numeric type is created but not written */
    int rank;             /* 1..3 (dims), 0: a scalar, -1: a null dataspace */
    hsize_t dims[3];      /* contiguous storage is allocated in full when written: keep it small */
    hsize_t chunk_rows;   /* 0: contiguous; else chunked (extendible) in chunks of that many rows */
    hsize_t write_rows;   /* rows written from the start (at most dims[0]); the rest is never written */
    const double *values; /* cycled over the elements written (NULL: all 0) */
    size_t nvalues;
} h5w_dataset_spec;
/* Replaces (or adds) the dataset object as spec describes. */
int h5w_replace_dataset_spec(hid_t file, const char *object, const h5w_dataset_spec *spec);
/* Writes (replacing) an attribute of group: n values converted to type
 * (rank 1), one value as a scalar (rank 0), or a null dataspace (rank -1). */
int h5w_set_attr(hid_t file, const char *group, const char *name, hid_t type, int rank, const double *values, int n);
/* Writes (replacing) a string attribute of group, fixed-length or (when
 * variable) variable-length. */
int h5w_set_string_attr(hid_t file, const char *group, const char *name, const char *value, int variable);
/* Removes attribute name of group. */
int h5w_delete_attr(hid_t file, const char *group, const char *name);
/* Adds an empty group (its parent must exist). */
int h5w_add_group(hid_t file, const char *object);
/* Adds (replacing) a link name to target: a hard link (target must exist)
 * or a soft one. */
int h5w_add_link(hid_t file, const char *name, const char *target, int hard);

#endif
