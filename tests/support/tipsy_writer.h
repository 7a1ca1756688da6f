/* A test-only Tipsy writer: makes files in either byte order and with either
 * header size, including deliberately bad headers, for the reader's tests
 * and the fuzz corpus. */
#ifndef ORR_TEST_TIPSY_WRITER_H
#define ORR_TEST_TIPSY_WRITER_H

#include <stdio.h>

/* Floats per record, in the Tipsy order of each family. */
#define TIPSY_GAS_FLOATS 12  /* mass, pos[3], vel[3], rho, temp, hsmooth, metals, phi */
#define TIPSY_DARK_FLOATS 9  /* mass, pos[3], vel[3], eps, phi */
#define TIPSY_STAR_FLOATS 11 /* mass, pos[3], vel[3], metals, tform, eps, phi */

typedef struct tipsy_writer_header {
    double time;
    int nbodies, ndim, nsph, ndark, nstar;
    int big_endian;  /* 1: standard XDR; 0: little-endian */
    int header_size; /* 32 (padded) or 28 */
} tipsy_writer_header;

/* The header of a consistent file with these counts. */
tipsy_writer_header tipsy_writer_header_for(double time, int nsph, int ndark, int nstar, int big_endian,
                                            int header_size);

/* Writes the header fields as given (they may be inconsistent on purpose).
 * Returns 0 on success. */
int tipsy_write_header(FILE *fp, const tipsy_writer_header *h);

/* Writes n floats in the header's byte order. Returns 0 on success. */
int tipsy_write_floats(FILE *fp, const float *v, size_t n, int big_endian);

/* Writes a whole file: header, then the gas, dark and star records (arrays
 * of nsph * 12, ndark * 9 and nstar * 11 floats; NULL when the count is 0).
 * Returns 0 on success. */
int tipsy_write_file(const char *path, const tipsy_writer_header *h, const float *gas, const float *dark,
                     const float *star);

#endif
