/* orrery-nbody's snapshots: Gadget-layout HDF5 files (docs/format-hdf5.md)
 * that orrery's own reader renders, and from which a run resumes exactly
 * where it was.
 *
 * Besides Gadget's header and PartTypeN groups (Coordinates, Velocities,
 * ParticleIDs, Masses, the initial conditions' other fields) a snapshot
 * keeps what a bit-for-bit resume needs and a Gadget file does not say:
 * positions and velocities in double (orrery's reader rounds them to float
 * for rendering), each particle's place in the run's memory order
 * (OrreryNbodyOrder: the tree's sums, hence the forces to the last bit,
 * depend on that order, and the Gadget layout groups particles by type),
 * with block time steps each particle's step (OrreryNbodyStepLevel: the
 * next steps are chosen from it), and in the group /OrreryNbody the step
 * count, the energy at step 0 and the integration settings. docs/nbody.md. */
#ifndef NBODY_SNAPSHOT_H
#define NBODY_SNAPSHOT_H

#include <stddef.h>
#include <stdint.h>

#include "core/error.h"
#include "orrery.h"
#include "particles/chunk.h"

/* A run's particles in its memory order: a view of them to write, or the
 * arrays a read allocates (nb_particles_free). */
typedef struct nb_particles {
    size_t n;
    double *pos, *vel, *mass; /* x, y, z of particle i at 3i */
    uint64_t *id;
    uint8_t *type;
    uint8_t *level; /* block time steps: particle i's last step is dt / 2^level[i]; NULL: none kept */
    int nfields;
    char field_name[ORR_ARRAYS_MAX_FIELDS][ORR_FIELD_NAME_MAX];
    float *field[ORR_ARRAYS_MAX_FIELDS];
} nb_particles;

/* What a resumed run takes up besides the particles. */
typedef struct nb_run_state {
    double time;  /* Header/Time */
    long step;    /* leapfrog steps done */
    long number;  /* the snapshot's number, NNNN in its name */
    double e0;    /* total energy at step 0 (the drift is reported against it) */
    double centre0[3]; /* the centre of mass at step 0 (its drift is reported against it) */
    int has_centre0;   /* read: the snapshot holds centre0 (older ones do not) */
    double dt, eps, eps_halo, theta;
    double eta;   /* block time steps' accuracy parameter; 0: one global step */
    double dt_min; /* block time steps' shortest step; 0: none (what snapshots without it had) */
    long snapshot_every;
    long tracer_neighbours; /* tracers' softening (0: as stars, what snapshots without it had) */
    long tracer_ring;       /* tracers' ring points (0: off, what snapshots without it had) */
    long tracer_mirror;     /* 1: half the ring's points mirrored (0: none, what snapshots without it had) */
    /* A snapshot in several files, one an MPI rank (--decompose): written,
     * the files (0 or 1: one) and every type's count over all of them
     * (NULL: this file's); read, the files and the count over all. */
    int nfiles;
    const uint64_t *type_totals;
    uint64_t total;
} nb_run_state;

/* The most particle types a snapshot holds (orrery's reader reads 16). */
#define NB_SNAPSHOT_TYPES 16

/* "DIR/snapshot_NNNN.hdf5"; 0, or -1 when it does not fit. */
int nb_snapshot_path(char *buf, size_t size, const char *dir, long number);

/* File `part` of snapshot `number` in nfiles files: "DIR/snapshot_NNNN.hdf5"
 * for one (nfiles <= 1), else "DIR/snapshot_NNNN.part.hdf5" (Gadget's
 * layout of a snapshot in several files, which orrery reads); 0 or -1. */
int nb_snapshot_part_path(char *buf, size_t size, const char *dir, long number, int part, int nfiles);

/* The newest snapshot in dir whose files are all there (a run killed
 * while its ranks wrote theirs may leave some of the newest): its number,
 * its files in *nfiles; or -1 with err. */
long nb_snapshot_newest_set(const char *dir, int *nfiles, orr_error *err);

/* The run state of a snapshot's file, without its particles; and into
 * names (when not NULL; no particles, nothing to free) the names of their
 * fields. */
orr_status nb_snapshot_read_state(const char *path, nb_run_state *s, nb_particles *names, orr_error *err);

/* Appends q's particles to p's (q's arrays are freed; p keeps block-step
 * levels only when both have them). 0, or -1 when out of memory or their
 * fields differ. */
int nb_particles_append(nb_particles *p, nb_particles *q);

/* Writes a snapshot to a temporary name beside path and renames it to path
 * once complete, so a run killed while writing leaves no partial file
 * under a snapshot's name. */
orr_status nb_snapshot_write(const char *path, const nb_particles *p, const nb_run_state *s, orr_error *err);

/* The number of the newest (highest-numbered) snapshot_NNNN.hdf5 in dir,
 * or -1 with err when dir cannot be read or holds none. */
long nb_snapshot_newest(const char *dir, orr_error *err);

/* Reads a snapshot orrery-nbody wrote, in double, back into the run's
 * memory order. */
orr_status nb_snapshot_read(const char *path, nb_particles *p, nb_run_state *s, orr_error *err);

void nb_particles_free(nb_particles *p);

#endif
