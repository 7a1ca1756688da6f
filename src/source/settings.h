/* The source stage's settings: the scene's input.* keys (docs/scenes.md#input),
 * except input.periodic.*, which the frame stage owns (frame/replicas.h).
 * The scene (scene/scene.h) holds one orr_input_settings; the renderer opens
 * the source they name (render/source_request.h: render/scene_source.c,
 * render/sequence_open.c). */
#ifndef ORR_SOURCE_SETTINGS_H
#define ORR_SOURCE_SETTINGS_H

#include <stdint.h>

#include "core/cards.h"
#include "core/keys.h"
#include "core/limits.h"
#include "core/names.h"
#include "particles/chunk.h"
#include "source/source.h"
#include "source/sequence.h"

/* Room for input.sequence.files: at most this many paths, in this many
 * bytes together (a pattern has no such limit). */
#define ORR_SEQ_FILES_MAX 1024
#define ORR_SEQ_FILES_BYTES 32768

/* input.model.*: a built-in model instead of a file (source/model.h, source/king.h). */
typedef struct orr_model_settings {
    char name[32];            /* input.model.name: "mw-m31" | "king"; empty when a file is used */
    long long particles;      /* input.model.particles (default 200000) */
    uint64_t seed;            /* input.model.seed (default 1) */
    double separation;        /* input.model.separation, kpc (default 780) */
    int galaxies;             /* input.model.galaxies: ORR_MODEL_PAIR (default), _MW, _M31 */
    double disc_q;            /* input.model.disc_q: the discs' Toomre Q (default 1.5) */
    double m31_weight;        /* input.model.m31_weight: M31's particles over the Milky Way's (default 1) */
    double w0;                /* input.model.w0: king's central potential W0 (default 7) */
    double core_radius;       /* input.model.core_radius: king's r0, pc (default 1) */
    double mass;              /* input.model.mass: king's total mass, Msun (default 5e5) */
    long long dust_particles; /* input.model.dust_particles: mw-m31's dusty gas discs, type 0,
                               * appended after the other particles (default 0: none) */
    double dust_clumping;     /* input.model.dust_clumping: their clouds and lanes, the sigma of
                               * the log of the gas density (default 0: smooth) */
} orr_model_settings;

/* input.sequence.*: snapshots interpolated in time (docs/sequences.md),
 * instead of input.file; listed by a pattern and a range, or by files. */
typedef struct orr_sequence_settings {
    char *pattern;               /* input.sequence.pattern: "snap_%03d.hdf5", resolved; owned, NULL when
                                  * none (core/owned.h) */
    long long first;             /* input.sequence.first (default 0) */
    long long last;              /* input.sequence.last (required with a pattern) */
    long long step;              /* input.sequence.step (default 1) */
    int nfiles;                  /* input.sequence.files: how many (0 when none) */
    char files[ORR_SEQ_FILES_BYTES]; /* ...the paths, resolved, one after another, each ending in NUL;
                                  * read them with orr_sequence_file */
    orr_interpolation interpolation; /* input.sequence.interpolation: auto | linear | hermite (default auto) */
    double max_memory;           /* input.sequence.max_memory: GiB two resident snapshots may take
                                  * (default 16) */
} orr_sequence_settings;

typedef struct orr_input_settings {
    char *file;               /* input.file, resolved; owned, NULL when a model is used (core/owned.h) */
    char format[32];          /* input.format: auto | a reader's name (default auto) */
    orr_model_settings model; /* input.model.* */
    char weight[ORR_FIELD_NAME_MAX]; /* input.weight: "mass" or a field name (default mass) */
    unsigned type_mask;       /* input.types: list of types 0..5 to draw; bit t set (default all, 0x3f) */
    long long chunk_size;     /* input.chunk: particles per chunk (default 1048576) */
    int skip_nonfinite;       /* input.nonfinite: error (0, default) | skip (1) */
    int insitu;               /* input.insitu: the particles come from a running simulation
                               * through orrery.h, which sets it; input.file and input.model.*
                               * are then optional and unused (default false) */
    orr_sequence_settings sequence; /* input.sequence.* */
} orr_input_settings;

/* The words of input.nonfinite (skip_nonfinite's 0 and 1). */
extern const orr_named orr_nonfinite_names[];

/* Fills d, which holds no strings (zeroed or freed), with the defaults above. */
void orr_input_settings_defaults(orr_input_settings *d);
/* d's owned strings (core/owned.h), at most ORR_INPUT_STRINGS, into fields; returns how many. */
#define ORR_INPUT_STRINGS 2
int orr_input_settings_strings(orr_input_settings *d, char **fields[]);
/* Frees d's strings. */
void orr_input_settings_free(orr_input_settings *d);
/* dst (its strings freed first) becomes a copy of src with strings of its own. */
orr_status orr_input_settings_copy(orr_input_settings *dst, const orr_input_settings *src, orr_error *err);

/* The input.* keys checked against each other: one input (a file, a
 * model or a sequence), each model's own keys, a sequence's pattern or
 * files; keys says which were given, and where (core/keys.h). */
orr_status orr_input_prepare(const orr_input_settings *in, const orr_keys *keys, orr_error *err);

/* Whether the input is a sequence of snapshots (a pattern or files). */
int orr_input_has_sequence(const orr_input_settings *in);
/* The i-th path of input.sequence.files. */
const char *orr_sequence_file(const orr_sequence_settings *d, int i);

/* What the renderer asks of the input besides its settings: which types
 * and fields it reads (what the drawn particles, the observer, the dust
 * need), and this process's share of a file. */
typedef struct orr_input_request {
    const char *scene_path;    /* for messages */
    unsigned reader_types;     /* the types a reader keeps (0: all; orr_source_options.type_mask) */
    unsigned model_types;      /* the types a built-in model generates (its markers always) */
    const char *const *fields; /* the extra fields a reader loads (NULL: all) */
    int nfields;
    int part, nparts;          /* this process's share of a file (a sequence's snapshot is read whole) */
} orr_input_request;

/* Opens the input: a built-in model (input.model.*), a file (input.file),
 * or a sequence's first snapshot (input.sequence.*, whose frames
 * orr_sequence_open opens for a run). Defined beside the models
 * (source/models/input.c). */
orr_status orr_input_open(const orr_input_settings *in, const orr_input_request *req, orr_source **out,
                          orr_error *err);

/* WEIGHT: the particle field deposited (input.weight). */
void orr_input_cards(const orr_input_settings *d, orr_cards *h);

#endif
