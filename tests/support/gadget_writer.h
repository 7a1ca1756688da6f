/* A small Gadget-1/2 snapshot writer for the tests and the benchmark only
 * (orrery itself never writes Gadget files). It streams: particle data come
 * from a callback, asked once per block per particle, so a file of any size
 * is written in constant memory. */
#ifndef ORR_TEST_GADGET_WRITER_H
#define ORR_TEST_GADGET_WRITER_H

#include <stdint.h>

/* Optional blocks (POS always, MASS whenever a type with particles has
 * massarr 0). */
enum {
    GW_VEL = 1 << 0,
    GW_ID = 1 << 1,
    GW_U = 1 << 2,    /* gas only, like RHO and HSML */
    GW_RHO = 1 << 3,
    GW_HSML = 1 << 4,
    GW_POT = 1 << 5
};

typedef struct gw_particle {
    double pos[3], vel[3];
    uint64_t id;
    double mass;          /* used when the type's massarr is 0 */
    double u, rho, hsml;  /* used for gas (type 0) */
    double pot;
} gw_particle;

/* Fills *p with particle i of the file (file order: type 0 first, ...). */
typedef void (*gw_particle_fn)(void *user, uint64_t i, int type, gw_particle *p);

typedef struct gw_spec {
    int snapformat;        /* 1 (no block labels) or 2 */
    int big_endian;
    int double_precision;  /* POS VEL MASS U RHO HSML POT as double */
    int id64;
    unsigned blocks;       /* GW_* flags */
    int32_t npart[6];      /* this file */
    double massarr[6];
    uint32_t npart_total[6], npart_total_high[6]; /* written as given */
    int32_t num_files;
    double time, redshift, box_size, omega0, omega_lambda, hubble_param;
    int32_t flag_sfr, flag_feedback, flag_cooling;
} gw_spec;

/* Writes one file; returns 0, or -1 with errno set (or EINVAL for a block
 * too long for a 32-bit record marker). */
int gw_write(const char *path, const gw_spec *spec, gw_particle_fn fn, void *user);

#endif
