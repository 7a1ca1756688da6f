/* A scene's snapshot sequence (input.sequence.*), opened once for a whole
 * animation: each frame then asks it for a source at its simulation time
 * (orr_sequence_source_at). docs/sequences.md. */
#ifndef ORR_RENDER_SEQUENCE_OPEN_H
#define ORR_RENDER_SEQUENCE_OPEN_H

#include "scene/scene.h"
#include "source/sequence.h"

/* Opens the sequence the scene lists (by pattern and range, or by files),
 * reading only each file's header, with the scene's input.format,
 * input.chunk, input.types, input.sequence.interpolation and
 * .max_memory, asking the readers for the given extra fields as
 * orr_scene_open_source does (fields NULL: all of them). Errors are
 * prefixed with the scene's path. A scene without a sequence is an error. */
orr_status orr_sequence_open_scene(const orr_scene *s, const char *const *fields, int nfields, orr_sequence **out,
                                   orr_error *err);

#endif
