/* A scene's snapshot sequence (input.sequence.*), opened once for a whole
 * animation: each frame then asks it for a source at its simulation time
 * (orr_sequence_source_at). docs/sequences.md. */
#ifndef ORR_RENDER_SEQUENCE_OPEN_H
#define ORR_RENDER_SEQUENCE_OPEN_H

#include "render/source_request.h"
#include "source/sequence.h"

/* Opens the sequence the request's input lists (by pattern and range, or by
 * files), reading only each file's header, with its input.format,
 * input.chunk, the types r->sequence_types, input.sequence.interpolation
 * and .max_memory, asking the readers for the given extra fields as
 * orr_source_request_open does (fields NULL: all of them). Errors are
 * prefixed with the scene's path. An input without a sequence is an error. */
orr_status orr_sequence_open_request(const orr_source_request *r, const char *const *fields, int nfields,
                                     orr_sequence **out, orr_error *err);

#endif
