/* The built-in model's dusty gas discs (docs/model.md#dust, docs/dust.md):
 * an opt-in component (input.model.dust_particles, 0 = none) appended after
 * the model's other particles, so the rest of the stream is unchanged when
 * it is off. One thin exponential disc of gas per galaxy, in the galaxy's
 * disc plane, on circular orbits; Gadget type 0 (gas), which a scene names
 * in dust.types and leaves out of input.types. Particle k is a pure function
 * of (seed, k), like the rest of the model. */
#ifndef ORR_SOURCE_MODEL_DUST_H
#define ORR_SOURCE_MODEL_DUST_H

#include <stdint.h>

#include "core/vecmath.h"

#define ORR_MODEL_TYPE_GAS 0
#define ORR_MODEL_DUST_VC_N 64 /* circular speed table, R = 0 .. rmax */

typedef struct orr_model_dust_disc {
    /* set by the model (its galaxy): */
    orr_vec3 centre, velocity, e1, e2, spin; /* spin = e1 x e2 */
    double vc[ORR_MODEL_DUST_VC_N];          /* circular speed at R = rmax i / (N - 1), km/s */
    /* set by orr_model_dust_add from the galaxy's gas description: */
    double gas_mass, rd, hz, rmax;           /* 1e10 Msun, kpc */
    uint64_t first, count;
    float mass;
} orr_model_dust_disc;

/* The clumping field's plane waves (orr_model_dust_init). */
#define ORR_MODEL_DUST_WAVES 96

typedef struct orr_model_dust {
    uint64_t total, seed;
    int ndisc;
    orr_model_dust_disc disc[2];
    /* Clumping: each particle's mass times exp(sigma g - sigma^2 / 2), g a
     * smooth Gaussian random field of unit variance at its place in its
     * galaxy's disc frame, the sum of plane waves k . x + phase. */
    double clumping;
    double wave[ORR_MODEL_DUST_WAVES][4]; /* kx, ky, kz (1/kpc), phase */
} orr_model_dust;

#define ORR_MODEL_DUST_MW 0
#define ORR_MODEL_DUST_M31 1

/* Starts a plan of total gas particles (0: none), clumped by clumping (the
 * sigma of the log of the gas density; 0: smooth). */
void orr_model_dust_init(orr_model_dust *d, uint64_t total, uint64_t seed, double clumping);
/* The next galaxy's disc (galaxy ORR_MODEL_DUST_MW or _M31): its gas mass
 * and sizes filled in; the caller sets the frame and the circular speeds. */
orr_model_dust_disc *orr_model_dust_add(orr_model_dust *d, int galaxy);
/* Shares the particles between the discs by gas mass. */
void orr_model_dust_split(orr_model_dust *d);

/* Gas particle k (0 .. total-1): position, velocity, mass and its distance
 * from its galaxy's centre. */
void orr_model_dust_make(const orr_model_dust *d, uint64_t k, orr_vec3 *pos, orr_vec3 *vel, float *mass,
                         float *r);

#endif
