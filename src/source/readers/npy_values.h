/* Values of NumPy arrays into particle chunks, shared by the .npy reader
 * and the .npz reader: what each named column becomes (x, y, z, mass, h,
 * id, type, or a named extra field), and each stored value decoded,
 * checked and stored. */
#ifndef ORR_SOURCE_NPY_VALUES_H
#define ORR_SOURCE_NPY_VALUES_H

#include <stddef.h>
#include <stdint.h>

#include "source/readers/npy_header.h"
#include "source/readers/share.h"
#include "source/source.h"

/* What each column becomes. */
enum { NPY_R_X, NPY_R_Y, NPY_R_Z, NPY_R_MASS, NPY_R_H, NPY_R_ID, NPY_R_TYPE, NPY_R_EXTRA, NPY_R_SKIP };

/* Gives each of the n columns its role (and an extra field's slot in the
 * chunk): x, y, z required, each role once, ids and types integers; extra
 * fields the options do not want are skipped. Sets info's has_h, has_id,
 * has_type and extra names. what names the file in messages; thing is
 * what a column is called there ("field", "member"), and positions says
 * how positions are given. */
orr_status npy_assign_roles(const char *what, const char *thing, const char *positions, const npy_column *col,
                            int n, int *role, int *slot, orr_source_info *info, const orr_source_options *opt,
                            orr_error *err);

/* One stored value at p into particle at of the chunk by its role;
 * refuses a bad mass, h, id or type with a message naming what and the
 * row. */
orr_status npy_store(const char *what, const npy_column *col, int role, int slot, orr_chunk *c, size_t at,
                     const unsigned char *p, int64_t row, orr_error *err);

/* One stored value as a double (integers of up to 8 bytes, floats). */
double npy_value(const npy_column *col, const unsigned char *p);

/* The float array a column of floats goes to (positions, mass, h, extra
 * fields), or NULL (ids, types, skipped columns). */
float *npy_float_target(int role, int slot, orr_chunk *c);

/* Values of a float column in the host's byte order, the first at base and
 * each stride bytes after the last, into out (npy_float_target's array), as
 * long as each is fine for its role (a mass by the mass policy, h finite
 * and not negative): plain loads instead of the general decoding. Returns
 * how many of the k were copied: k, or the index of the first value left to
 * npy_store (whose message names it); 0 for any other column. */
size_t npy_copy_native_floats(const npy_column *col, int role, const unsigned char *base, size_t stride, size_t k,
                              float *out);

/* Mass 1 (when has_mass is 0), ids from the row and type 0 where the file
 * gives none, for k particles from at on, the first of row `row`. */
/* Reads one block of k rows into chunk rows c->n .. c->n + k - 1. */
typedef orr_status (*npy_block_fn)(orr_source *src, size_t k, orr_error *err);

/* Fills src's chunk from *row on with the rows of the share, in blocks of
 * at most `block` rows each read by read_block (both numpy readers). */
orr_status npy_fill_chunk(orr_source *src, const orr_share *share, size_t block, int64_t *row,
                          npy_block_fn read_block, orr_error *err);

void npy_defaults(const orr_source_info *info, int has_mass, orr_chunk *c, size_t at, size_t k, int64_t row);

#endif
