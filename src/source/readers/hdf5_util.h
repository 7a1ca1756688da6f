/* Small helpers over the HDF5 C API for the snapshot reader: attributes read
 * whatever their stored numeric type and whether they are scalars or SWIFT's
 * 1-element arrays, dataset shapes, hyperslab reads, and HDF5's own error
 * text, so that every failure becomes an orr_error message. */
#ifndef ORR_SOURCE_HDF5_UTIL_H
#define ORR_SOURCE_HDF5_UTIL_H

#include <hdf5.h>
#include <stddef.h>
#include <stdint.h>

/* Stops HDF5 printing its error stack on stderr: the library never prints. */
void orr_h5_quiet(void);

/* Copies the innermost description on HDF5's error stack into buf ("" when
 * the stack is empty) and clears the stack; returns buf. */
const char *orr_h5_reason(char *buf, size_t size);

/* Closes an identifier of any kind when it is valid; returns -1 so callers
 * can write `id = orr_h5_close(id)`. */
hid_t orr_h5_close(hid_t id);

/* Whether loc has a link called name (no error when it has not). */
int orr_h5_has_link(hid_t loc, const char *name);

typedef enum {
    ORR_H5_ABSENT = 0,   /* no such attribute */
    ORR_H5_FOUND = 1,    /* read; *count elements */
    ORR_H5_WRONG_TYPE,   /* not numbers (or not a string for the string reader) */
    ORR_H5_TOO_MANY,     /* more than max elements; *count says how many */
    ORR_H5_UNREADABLE    /* HDF5 failed to read it (see orr_h5_reason) */
} orr_h5_attr_result;

/* Reads the numeric attribute name of loc converted to memtype (e.g.
 * H5T_NATIVE_DOUBLE, H5T_NATIVE_INT64) into out[0 .. max); a scalar counts
 * as one element. */
orr_h5_attr_result orr_h5_attr_numbers(hid_t loc, const char *name, hid_t memtype, void *out, int max,
                                       int *count);

/* Reads a string attribute (fixed or variable length, scalar or one element)
 * into buf, cut to size - 1 characters. */
orr_h5_attr_result orr_h5_attr_string(hid_t loc, const char *name, char *buf, size_t size);

/* The shape of a dataset: its rank (at most ORR_H5_MAX_RANK dims filled) and
 * type class; returns -1 when HDF5 cannot tell. */
#define ORR_H5_MAX_RANK 32
int orr_h5_dataset_shape(hid_t ds, hsize_t *dims, H5T_class_t *cls);

/* How a dataset is stored: the bytes of one HDF5 chunk (0 when it is not
 * chunked), the bytes stored in the file, and whether it is a virtual
 * dataset (whose data live in other files, so stored bytes say nothing). */
typedef struct orr_h5_storage {
    uint64_t chunk_bytes;
    uint64_t stored_bytes;
    uint64_t element_bytes;
    int is_virtual;
} orr_h5_storage;
void orr_h5_storage_info(hid_t ds, orr_h5_storage *out);

/* Reads rows [first, first + n) of a 1-D dataset (ncols == 0) or of a 2-D
 * dataset with ncols columns into buf, converted to memtype. Returns 0 on
 * success, -1 on an HDF5 failure. */
int orr_h5_read_rows(hid_t ds, uint64_t first, size_t n, int ncols, hid_t memtype, void *buf);

/* Reads rows [first, first + n) of column col of a 2-D dataset into buf
 * (n values), converted to memtype. Returns 0 on success, -1 on failure. */
int orr_h5_read_column(hid_t ds, uint64_t first, size_t n, int col, hid_t memtype, void *buf);

#endif
