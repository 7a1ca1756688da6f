/* Small helpers for writing HDF5 snapshots in the Gadget layout (the
 * generated initial conditions of zeldovich_hdf5.c, orrery-nbody's
 * snapshots): attributes, groups and whole datasets written without
 * modification times (so equal contents give equal bytes), and a file
 * written under a temporary name and renamed into place only when complete
 * (encode/atomic.h), with the system's reason in the message when it fails. */
#ifndef ORR_SOURCE_HDF5_WRITE_H
#define ORR_SOURCE_HDF5_WRITE_H

#include <hdf5.h>

#include "core/error.h"

/* Writes n numbers (a scalar when n == 0) as attribute name of loc, stored
 * as ftype from memory of mtype. Returns 1 when it failed, else 0. */
int orr_h5w_attr(hid_t loc, const char *name, hid_t ftype, hid_t mtype, const void *v, int n);
int orr_h5w_double(hid_t loc, const char *name, double v);
/* A string attribute (scalar, fixed length). */
int orr_h5w_string(hid_t loc, const char *name, const char *s);

/* Creates group name in loc (close it with H5Gclose or
 * orr_h5w_close_group); < 0 when it failed. */
hid_t orr_h5w_group(hid_t loc, const char *name);
/* Closes a group: 1 when the close failed or bad was already set, else 0. */
int orr_h5w_close_group(hid_t group, int bad);

/* Writes a whole dataset of rows x cols values (1-D when cols == 1).
 * Returns 1 when it failed, else 0. */
int orr_h5w_dataset(hid_t group, const char *name, hid_t ftype, hid_t mtype, const void *data, hsize_t rows,
                    int cols);

/* Creates the file path through a temporary file, has write_body fill it
 * (returning non-zero when something failed), and renames it to path only
 * when everything was written and flushed; otherwise the temporary file is
 * removed and err names path (and the system's reason, e.g. a full disk). */
typedef int (*orr_h5w_body)(hid_t file, void *ctx);
orr_status orr_h5w_write_file(const char *path, orr_h5w_body write_body, void *ctx, orr_error *err);

#endif
