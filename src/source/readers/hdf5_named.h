/* Named HDF5 fields: any numeric dataset of a particle group, asked for by
 * name as a field (input.weight, a colour population's field): SWIFT's
 * StellarFormationTime, an EAGLE or AREPO Metallicity, Temperatures...
 * A 1-D dataset is named as it is ("StellarFormationTime"); one column of
 * a 2-D dataset as "Name[k]" ("MetalMassFractions[0]", k from 0). */
#ifndef ORR_SOURCE_HDF5_NAMED_H
#define ORR_SOURCE_HDF5_NAMED_H

#include <hdf5.h>

#include "core/error.h"
#include "particles/chunk.h"

#define H5R_MAX_NAMED 8

typedef struct h5r_named {
    char field[ORR_FIELD_NAME_MAX];   /* as asked for: "MetalMassFractions[0]" */
    char dataset[ORR_FIELD_NAME_MAX]; /* the dataset: "MetalMassFractions" */
    int column;                       /* -1: a 1-D dataset; else the column read */
    int present;                      /* some group read has the dataset */
    int slot;                         /* its index among the chunk's extra fields, or -1 */
    hid_t ds;                         /* the dataset in the group being read, or -1 */
} h5r_named;

/* Splits a field name into dataset and column; 0 when it is not a name a
 * dataset can have ("", a bad "[k]", a '/' or '.' that would leave the group). */
int h5r_named_parse(const char *field, h5r_named *out);

/* Checks f's dataset in group g of file path (type t, n particles), when g
 * has it: n rows, 1-D (or 2-D with the column inside), numbers. Marks f
 * present. The message names file, group, dataset and what was wrong. */
orr_status h5r_named_check(h5r_named *f, const char *path, int t, hid_t g, int64_t n, orr_error *err);

/* The error for a field f that no group read has, listing the datasets
 * of the first group read in file fid (path). */
orr_status h5r_named_missing(const h5r_named *f, const char *path, hid_t fid, unsigned type_mask, int ntypes,
                             orr_error *err);

/* Opens f's dataset in group g when it has it (else f->ds = -1). */
orr_status h5r_named_open(h5r_named *f, const char *path, int t, hid_t g, orr_error *err);

/* Reads rows [row, row + n) of f into out as floats (0 when the group being
 * read has no such dataset). */
orr_status h5r_named_read(const h5r_named *f, const char *path, int t, uint64_t row, size_t n, float *out,
                          orr_error *err);

#endif
