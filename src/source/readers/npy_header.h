/* The header of a NumPy .npy file (numpy's format.py, versions 1 to 3):
 * the magic "\x93NUMPY", a version, the header's length and a Python dict
 * literal naming the dtype, the order and the shape. Parsed by a small,
 * bounded parser of that literal: any bytes give either a description the
 * reader can trust (sizes consistent, no overflow) or a message saying what
 * is wrong. */
#ifndef ORR_SOURCE_NPY_HEADER_H
#define ORR_SOURCE_NPY_HEADER_H

#include <stddef.h>
#include <stdint.h>

#include "particles/chunk.h"

#define NPY_MAX_COLUMNS 64
#define NPY_MAX_HEADER (1u << 20) /* header bytes: numpy's own are a few hundred */
#define NPY_PREAMBLE_V1 10        /* magic 6, version 2, length 2 */
#define NPY_PREAMBLE_V2 12        /* magic 6, version 2, length 4 */

typedef enum { NPY_FLOAT, NPY_INT, NPY_UINT, NPY_PAD } npy_kind;

typedef struct npy_column {
    char name[ORR_FIELD_NAME_MAX]; /* "x", "mass", ...; "" for padding */
    npy_kind kind;
    int size;      /* bytes: 1, 2, 4, 8 (floats 4 or 8); any for padding */
    int big;       /* stored big-endian */
    size_t offset; /* within a row (C order) */
} npy_column;

typedef struct npy_header {
    int version;
    size_t header_len;     /* the dict's bytes */
    int64_t data_offset;   /* where the rows start */
    int64_t rows;          /* N */
    int structured;        /* 1: named fields, shape (N,); 0: a plain (N, 3) array */
    int fortran;           /* a plain array stored column by column */
    int ncolumns;
    npy_column col[NPY_MAX_COLUMNS];
    size_t record;         /* bytes a row */
    /* Set by the caller between the preamble and the dict: accept any
     * plain array of 0 to 2 dimensions (an .npz member): a scalar (rows 1,
     * ndim 0), (N,) or (N, k) of floats or integers, its columns unnamed. */
    int any_shape;
    int ndim;              /* 0, 1 or 2 (any_shape; else 1 structured, 2 plain) */
} npy_header;

/* Checks the preamble (the first n bytes, at least NPY_PREAMBLE_V2 when the
 * file has them): returns 1 and sets version, header_len and data_offset,
 * or 0 with why. */
int npy_parse_preamble(const unsigned char *head, size_t n, npy_header *h, char *why, size_t size);

/* Parses the header dict (len bytes of text) into h; 0 with why when it is
 * not one this reader can read. */
int npy_parse_dict(const char *text, size_t len, npy_header *h, char *why, size_t size);

/* Whether the first n bytes of a file are a .npy file's magic. */
int npy_has_magic(const unsigned char *head, size_t n);

#endif
