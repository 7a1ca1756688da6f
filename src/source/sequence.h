/* A sequence of snapshots of one simulation, read as a source at any time
 * between the first and the last: positions are interpolated in time between
 * the two snapshots that bracket it, particles matched by id. At most two
 * snapshots are held in memory; stepping forward through time reads each
 * snapshot once. docs/sequences.md has the maths and the memory it needs. */
#ifndef ORR_SOURCE_SEQUENCE_H
#define ORR_SOURCE_SEQUENCE_H

#include <stddef.h>
#include <stdint.h>

#include "core/names.h"

#include "source/source.h"

typedef enum {
    ORR_INTERP_AUTO,    /* hermite when both snapshots have velocities, else linear */
    ORR_INTERP_LINEAR,  /* x = (1 - s) x0 + s x1 */
    ORR_INTERP_HERMITE, /* cubic Hermite from positions and velocities */
} orr_interpolation;

/* "auto", "linear", "hermite". */
extern const orr_named orr_interpolation_names[];
const char *orr_interpolation_name(orr_interpolation k);
/* 1 and *k when w names an interpolation, else 0. */
int orr_interpolation_from_name(const char *w, orr_interpolation *k);

/* input.sequence.max_memory's default: 16 GiB. */
#define ORR_SEQUENCE_DEFAULT_MAX_MEMORY (16.0 * 1024.0 * 1024.0 * 1024.0)

typedef struct orr_sequence_options {
    /* How to read each file: format, chunk size of the sources handed out,
     * the types wanted (others are not kept in memory) and the extra fields
     * wanted (NULL: every field the files have). Velocities are read as
     * well when the interpolation may be hermite. The field names are
     * copied. */
    orr_source_options source;
    orr_interpolation interpolation;
    double max_memory; /* bytes two resident snapshots may take; 0: the default */
    /* A periodic box's side (0: not periodic). A particle that leaves
     * through one face and comes back through the opposite one between two
     * snapshots moves by the shortest displacement (the minimum image),
     * through the face, not back across the box; interpolated positions are
     * wrapped into [0, box). The sources carry it as a BoxSize header. */
    double box;
} orr_sequence_options;

typedef struct orr_sequence_stats {
    long loads;                 /* snapshots read into memory since the sequence was opened */
    int64_t matched;            /* particles in the last source handed out */
    int64_t only_earlier;       /* ...dropped because the later snapshot lacks their id */
    int64_t only_later;         /* ...dropped because the earlier snapshot lacks their id */
    int hermite;                /* whether the last source used hermite interpolation */
} orr_sequence_stats;

typedef struct orr_sequence orr_sequence;

/* Checks that pattern holds exactly one integer conversion (%d, %i, %u, %x,
 * %X or %o, with flags, width and precision such as %03d; no length
 * modifier), every other '%' written as "%%". */
orr_status orr_sequence_pattern_check(const char *pattern, orr_error *err);

/* The pattern with number in place of its conversion ("snap_%03d.hdf5", 7 ->
 * "snap_007.hdf5"). */
orr_status orr_sequence_pattern_path(const char *pattern, long number, char *out, size_t size, orr_error *err);

/* Opens a sequence of npaths files (at least 2). Reads only each file's
 * header: their times must strictly increase (an error names both files and
 * their times otherwise), and two neighbours' estimated memory must fit
 * opt->max_memory. */
orr_status orr_sequence_open(const char *const *paths, int npaths, const orr_sequence_options *opt,
                             orr_sequence **out, orr_error *err);

/* The same for the files pattern(first), pattern(first + step), ... up to
 * last (inclusive); a missing file is an error that names it. */
orr_status orr_sequence_open_pattern(const char *pattern, long first, long last, long step,
                                     const orr_sequence_options *opt, orr_sequence **out, orr_error *err);

/* Number of snapshots, and snapshot k's path and simulation time. */
int orr_sequence_count(const orr_sequence *seq);
const char *orr_sequence_path(const orr_sequence *seq, int k);
double orr_sequence_time(const orr_sequence *seq, int k);

/* The first and last snapshots' times: the default of animation.time. */
void orr_sequence_time_range(const orr_sequence *seq, double *t0, double *t1);

/* Bytes per particle of one resident snapshot, from the first file's header
 * (positions, mass, id, type, h, velocities and extra fields kept). */
size_t orr_sequence_bytes_per_particle(const orr_sequence *seq);

/* A source yielding the particles at simulation time `time` (in id order),
 * in chunks of opt->source.chunk_size. At a snapshot's own time: that
 * snapshot's particles, bit for bit. Between two: the particles present in
 * both, interpolated (through the faces of a periodic box, opt->box); the
 * rest are dropped and counted in the stats. Mass,
 * type and extra fields are the earlier snapshot's; h is interpolated
 * linearly. A time outside the sequence is an error.
 * The source reads memory the sequence owns: it stays valid until the next
 * orr_sequence_source_at or orr_sequence_close (after which its next() and
 * rewind() fail), and closing it frees only the source itself. A sequence
 * is not thread-safe: use one per thread. */
orr_status orr_sequence_source_at(orr_sequence *seq, double time, orr_source **out, orr_error *err);

orr_sequence_stats orr_sequence_get_stats(const orr_sequence *seq);

/* Frees the sequence and the snapshots it holds; seq may be NULL. */
void orr_sequence_close(orr_sequence *seq);

#endif
