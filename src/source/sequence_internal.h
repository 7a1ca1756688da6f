/* What the snapshot sequence's files share: sequence.c (the sequence, its
 * files and headers), sequence_load.c (a snapshot read into memory, sorted
 * by id) and sequence_source.c (the source interpolated between two). */
#ifndef ORR_SOURCE_SEQUENCE_INTERNAL_H
#define ORR_SOURCE_SEQUENCE_INTERNAL_H

#include <stddef.h>
#include <stdint.h>

#include "source/sequence.h"

#define NVEL 3
static const char *const VEL_NAMES[NVEL] = {"vx", "vy", "vz"};

/* One snapshot held in memory, sorted by id. */
typedef struct snapshot {
    int index; /* which file of the sequence; -1: the slot is empty */
    size_t n;
    float *x, *y, *z, *mass, *h; /* h NULL when the file has none */
    uint64_t *id;
    uint8_t *type;
    int has_id, has_type;
    double h_support;
    char mass_unit[32], length_unit[16]; /* the file's FITS units (source.h), "" unknown */
    int nextra;
    char names[ORR_MAX_EXTRA_FIELDS][ORR_FIELD_NAME_MAX];
    float *extra[ORR_MAX_EXTRA_FIELDS];
    int vel[NVEL]; /* indices of vx, vy, vz among the extras; -1 when absent */
} snapshot;

struct orr_sequence {
    int n;
    char **paths;
    double *times;
    orr_sequence_options opt;
    int nfields;                  /* fields asked of the reader (caller's plus velocities), -1: all */
    const char *fields[ORR_MAX_EXTRA_FIELDS + NVEL];
    char field_store[ORR_MAX_EXTRA_FIELDS + NVEL][ORR_FIELD_NAME_MAX];
    int ncaller;                  /* the caller's own fields: the first ncaller of them; -1: all */
    size_t bytes_per_particle;
    snapshot slot[2];
    unsigned long generation;     /* bumped by every orr_sequence_source_at */
    orr_sequence_stats stats;
};

/* Opens file k of the sequence for reading with the fields it asks for. */
orr_status orr_seq_open_file(const orr_sequence *seq, int k, orr_source **src, orr_error *err);
/* Bytes a snapshot holds per particle of a file described by info. */
size_t orr_seq_bytes_per_particle(const orr_source_info *info);
/* Bytes in GiB, for messages. */
static inline double gib(double bytes) { return bytes / (1024.0 * 1024.0 * 1024.0); }

/* Frees a held snapshot and marks its slot empty. */
void orr_seq_snapshot_free(snapshot *sn);

/* Makes snapshots a and b (b = -1: none) resident in the two slots. */
orr_status orr_seq_require(orr_sequence *seq, int a, int b, snapshot **sa, snapshot **sb, orr_error *err);

#endif
