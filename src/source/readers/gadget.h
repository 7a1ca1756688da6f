/* Gadget-1/2 binary snapshots (SnapFormat 1 and 2), either byte order,
 * single or multi-file (snap.0, snap.1, ...), float or double fields, 32- or
 * 64-bit ids. docs/format-gadget.md describes what is read and checked.
 *
 * Particles come out file by file and, within a file, type by type (the
 * order of the file). chunk->type is the Gadget type 0..5; types outside
 * opt->type_mask are skipped without reading their data. Extra fields, loaded
 * only when opt->fields asks for them (NULL: all the file has): vx vy vz
 * (VEL), u, rho (gas only; 0 for other types) and pot (POT). HSML goes to
 * chunk->h (0 for non-gas particles) whenever the file has it. */
#ifndef ORR_SOURCE_GADGET_H
#define ORR_SOURCE_GADGET_H

#include <stddef.h>

#include "source/source.h"

/* Recognises the first Fortran record of a Gadget file: 256 (the header,
 * SnapFormat 1) or 8 followed by "HEAD" (SnapFormat 2), in either byte order. */
int orr_gadget_probe(const unsigned char *head, size_t n);

/* Opens path, which names a single file, one part of a multi-file snapshot
 * ("snap_010.0") or the snapshot's base name ("snap_010" when only
 * "snap_010.0", "snap_010.1", ... exist). Reads every part's header and
 * checks every record's length against the file size and the particle
 * counts before allocating anything. */
orr_status orr_gadget_source_open(const char *path, const orr_source_options *opt, orr_source **out,
                                  orr_error *err);

#endif
