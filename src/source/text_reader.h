/* Plain-text particle tables: a header line naming the columns, then one
 * particle per line, separated by white space or commas. Recognised columns:
 * x y z (required), mass (or m; default 1), h (smoothing length), id (default:
 * the row number from 0), type (0..5); any other column becomes a named extra
 * field. Lines starting with '#' and blank lines are skipped. */
#ifndef ORR_SOURCE_TEXT_READER_H
#define ORR_SOURCE_TEXT_READER_H

#include "source/source.h"

orr_status orr_text_source_open(const char *path, size_t chunk_size, orr_source **out, orr_error *err);

#endif
