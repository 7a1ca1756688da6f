/* Plain-text particle tables: a header line naming the columns, then one
 * particle per line, separated by white space or commas. Recognised columns:
 * x y z (required), mass (or m; default 1), h (smoothing length), id (default:
 * the row number from 0), type (0..5); any other column becomes a named extra
 * field. Lines starting with '#' and blank lines are skipped. */
#ifndef ORR_SOURCE_TEXT_READER_H
#define ORR_SOURCE_TEXT_READER_H

#include "source/source.h"

#include <stddef.h>
#include <stdio.h>

/* Loads every column whatever opt->fields says: text tables are small. */
orr_status orr_text_source_open(const char *path, const orr_source_options *opt, orr_source **out,
                                orr_error *err);

/* Reads a table from a stream that cannot seek (standard input, a FIFO):
 * head holds its first n bytes, already taken by format detection, which
 * are read first. name stands for the stream in messages. The source closes
 * fp when owns_fp is set (also when opening fails); it cannot be rewound. */
orr_status orr_text_source_open_stream(const char *name, FILE *fp, int owns_fp, const unsigned char *head,
                                       size_t n, const orr_source_options *opt, orr_source **out, orr_error *err);

/* Recognises text: no NUL and no control characters other than white space. */
int orr_text_probe(const unsigned char *head, size_t n);

#endif
