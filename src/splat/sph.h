/* SPH kernel deposit: each particle spreads its weight over the pixels its
 * smoothing kernel covers, as the column kernel F (splat/kernel.h)
 * integrated over each pixel's area, so a particle much smaller than a
 * pixel still puts exactly its weight into the pixel(s) it overlaps and a
 * large one is smooth. Weight is conserved to round-off: what lands in the
 * image plus what falls off it equals the weight of the visible particles,
 * whatever the smoothing lengths.
 *
 * Flat projections (orthographic, perspective): the kernel is a circle of
 * radius 2 h_pix, h_pix = h * scale (the projection's local pixels per unit
 * length). Sky maps (Hammer-Aitoff, dome master, equirectangular): the
 * kernel is a cap of angular radius set by h / r on the sphere of
 * directions, drawn with the map's own distortion; footprints crossing the
 * l = +-180 seam, a pole or the dome's rim are drawn on both sides or
 * folded onto the map, and pixels outside the map never receive weight.
 * docs/smoothing.md describes the methods and their accuracy.
 *
 * Usage, FFTW-style: set up once per kernel and projection, then deposit
 * block after block:
 *
 *   orr_sph sph;
 *   orr_sph_init(&sph, &kernel, &proj, &err);
 *   for each block: orr_project_batch(...); orr_sph_deposit(&sph, &block, &plane, &stats);
 *   orr_sph_free(&sph);
 *
 * orr_sph_deposit only reads the orr_sph, so threads may share one, each
 * depositing into its own plane. */
#ifndef ORR_SPLAT_SPH_H
#define ORR_SPLAT_SPH_H

#include <stddef.h>
#include <stdint.h>

#include "frame/projection.h"
#include "splat/deposit.h"
#include "splat/kernel.h"
#include "core/plane.h"

/* Sky maps are indexed, once, in tiles of ORR_SPH_TILE pixels a side,
 * grouped ORR_SPH_GROUP x ORR_SPH_GROUP into coarse tiles, so that a large
 * kernel visits only the pixels it can reach; and in cells of
 * ORR_SPH_CELL pixels that say how large a kernel the map's local affine
 * model draws faithfully there. */
#define ORR_SPH_TILE 8
#define ORR_SPH_GROUP 8
#define ORR_SPH_CELL 16

/* A tile's directions: all its pixel centres on the map lie within the
 * angle r of the unit vector (x, y, z); cos_r = 2 (never reached) for a
 * tile with none on the map. */
typedef struct orr_sph_tile {
    float x, y, z, cos_r, sin_r;
} orr_sph_tile;

/* The largest sky map (pixels) given per-pixel tables: 32 bytes a pixel. */
#define ORR_SPH_PIXEL_TABLE_MAX (1 << 21)

typedef struct orr_sph {
    const orr_kernel *kernel;
    orr_projection proj;
    int sky;
    /* Sky maps only. */
    double omega;              /* every pixel's solid angle on an equal-area map, else 0 */
    int tiles_x, tiles_y, groups_x, groups_y, cells_x, cells_y;
    orr_sph_tile *tiles;       /* tiles_x * tiles_y */
    orr_sph_tile *groups;      /* groups_x * groups_y */
    float *safe;               /* per cell: the largest support radius (pixels) the affine model draws */
    /* Equirectangular maps: the pixel centres' directions and solid angles,
     * exactly as orr_unproject and the projection's scale give them, so the
     * exact path maps a pixel back without trigonometry. */
    double *eq_lon;            /* per column: -sin l and cos l (2 * width) */
    double *eq_lat;            /* per row: cos b and -sin b (2 * height) */
    double *eq_omega;          /* per pixel: its solid angle (width * height) */
    /* Other sky maps of at most ORR_SPH_PIXEL_TABLE_MAX pixels (the coarse
     * glow's maps): every pixel centre's direction and solid angle (0 off
     * the map), as orr_unproject and the projection's scale give them, for
     * the exact path's kernels tens of degrees wide. */
    double *px_dir;            /* per pixel: x, y, z (3 * width * height) */
    double *px_omega;          /* per pixel: its solid angle, 0 off the map */
    /* Maps with an outline (the dome's circle, the Hammer-Aitoff ellipse):
     * each row's run of pixels on the map, [2 j] to [2 j + 1] (exclusive),
     * exactly orr_projection_pixel_in_map's answers, looked up where a
     * footprint crosses the outline (a test per pixel there); else NULL. */
    int *row_on_map;
    struct orr_sky_cores *cores; /* a sky map's PSF cores drawn from stamps (splat/sky_cores.h), or NULL */
    struct orr_healpix_budget *healpix_budget; /* a HEALPix map's work limit (splat/healpix_kernel.h), or NULL */
} orr_sph;

/* One block of particles as the renderer holds it after orr_project_batch. */
typedef struct orr_sph_block {
    size_t n;
    const float *x, *y, *z;      /* camera-frame positions, used by sky maps; may be NULL (a sky map then
                                  * draws every kernel flat at its local scale, folded onto the map) */
    const float *px, *py, *scale;/* image position and pixels per unit length (orr_project_batch) */
    const uint8_t *visible;      /* 0 when the projection did not draw the particle */
    const float *h;              /* smoothing lengths, in the units of x, y, z; NULL: none */
    const float *w;              /* weights */
} orr_sph_block;

/* Sets up the deposit for a kernel (which must outlive it) and a
 * projection (copied; it must have been set up). For a sky map this
 * indexes the map, about 0.1 s for a 3600 x 3600 dome master. */
orr_status orr_sph_init(orr_sph *s, const orr_kernel *k, const orr_projection *proj, orr_error *err);
void orr_sph_free(orr_sph *s);

/* A sky map whose particles are widened to a PSF core of angular size
 * theta = h / r (post/view_psf.h): those whose kernel is the core alone
 * are drawn from a table of pixel-integrated stamps (splat/sky_cores.h)
 * instead of being evaluated one by one. Nothing for a flat projection. */
orr_status orr_sph_use_cores(orr_sph *s, double theta, orr_error *err);

/* For splat/sky_cores.c: a kernel of angular size theta at image point
 * (px, py) as the local affine model draws it, the ellipse u = a dx^2 +
 * 2 b dx dy + c dy^2 < 4 of half-extents ex, ey pixels, where the model
 * holds over the whole support on the map (0 elsewhere); */
typedef struct orr_sph_core_shape {
    double a, b, c, ex, ey;
} orr_sph_core_shape;
int orr_sph_core_ellipse(const orr_sph *s, double px, double py, double theta, orr_sph_core_shape *shape);
/* its weights, as the deposit computes them, centred at (cx, cy) of a
 * width x height stamp (row by row, pixel (0, 0) at the stamp's corner),
 * unnormalised; returns their sum; */
double orr_sph_core_stamp(const orr_sph *s, const orr_sph_core_shape *shape, double cx, double cy, int width,
                          int height, float *out);
/* and the support radius (pixels) the map's index says the affine model
 * draws faithfully at (px, py): 0 near the map's outline. */
float orr_sph_affine_reach(const orr_sph *s, double px, double py);

/* Deposits a block into plane (the projection's size). Particles without a
 * smoothing length (h NULL, or h[i] zero, negative or not finite) are
 * deposited cloud-in-cell, as orr_deposit does. Adds to stats as
 * orr_deposit does: deposited + outside + culled = the block's weight (on
 * sky maps nothing is outside). The cost of a particle is about that of
 * its footprint; on a sky map a kernel covering much of the sky (an
 * observer inside or near it) costs up to a pass over the map. */
void orr_sph_deposit(const orr_sph *s, const orr_sph_block *b, orr_plane *plane, orr_deposit_stats *stats);

/* orr_sph_deposit of the block into each of nplanes planes, with weights
 * w[k] for planes[k] (b->w unused) and statistics into stats[k]: the same
 * bits. On a sky map each kernel's footprint (its pixels' weights, or the
 * core table's look-up, orr_sph_use_cores) is found once for every plane. */
void orr_sph_deposit_planes(const orr_sph *s, const orr_sph_block *b, const float *const *w, orr_plane *planes,
                            int nplanes, orr_deposit_stats *stats);

#endif
