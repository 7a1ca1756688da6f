/* Writes the particles of any source as a plain-text table that the text
 * reader (source/readers/text_reader.h) reads back exactly: a header line
 * "x y z mass [h] id type [extra fields...]", then one particle per line.
 * Floats are printed with 9 significant digits, enough for every float32 to
 * round-trip bit for bit; ids and types are printed as integers. */
#ifndef ORR_SOURCE_TEXT_WRITER_H
#define ORR_SOURCE_TEXT_WRITER_H

#include "source/source.h"

/* Reads src from its current position to the end and writes the particles to
 * path. The file appears under its name only when complete (written to a
 * temporary file beside it, then renamed); on any error no file is left.
 * Errors: ORR_ERR_IO naming the file (cannot create, disk full, ...),
 * ORR_ERR_USAGE for a field name that cannot be a text column, or whatever
 * the source reports while being read. */
orr_status orr_text_write_source(orr_source *src, const char *path, orr_error *err);

#endif
