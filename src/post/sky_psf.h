/* A Hubble-like (or FITS) PSF on a sky map: dome master, Hammer-Aitoff,
 * equirectangular (docs/psf.md, "Sky maps and dome masters").
 *
 * Every star is first drawn as the PSF's core: its SPH kernel widened to
 * the core's angular FWHM (view_psf.h), with all of its flux. The brightest
 * stars (psf.spike_stars of them, no fainter than psf.spike_min_flux of the
 * brightest) are then redrawn with the whole PSF: their core deposit is
 * taken away again (the same deposit with the opposite weight) and the PSF
 * image is stamped in its place, sampled in the star's tangent plane, so
 * spikes and rings keep their angular length and their angle to the local
 * north wherever the star is on the map. Each stamp is normalised to the
 * star's flux, so every star keeps exactly its flux whether it has spikes
 * or not. Faint stars, whose wings would not show, keep their core: that
 * is what keeps millions of particles cheap.
 *
 * Directions: the tangent plane at star s has north towards the camera's
 * up (-y: b = +90 on the panoramas, the top of a dome master) and east
 * towards the image's +x at the map's centre, so a star at the centre looks
 * as it would on a flat image; the PSF's angle is counterclockwise from
 * east with north up, as on a flat image from x with y up. */
#ifndef ORR_POST_SKY_PSF_H
#define ORR_POST_SKY_PSF_H

#include "post/convolve.h"
#include "reduce/parallel.h"
#include "splat/sph.h"

/* Splat lanes that may collect stars at once (reduce/lanes.h's ORR_MAX_LANES). */
#define ORR_SKY_PSF_LANES 8
/* The zeros around the PSF's padded copy, on every side. */
#define ORR_SKY_PSF_PAD 2

/* A bright star as it was deposited, so that deposit can be undone. */
typedef struct orr_sky_star {
    float key;                       /* its brightness: Y with colour, else the weight */
    float x, y, z, px, py, scale, h; /* camera frame, image position and scale, smoothing length */
    float w[ORR_PLANES_MAX];         /* weights of the planes */
} orr_sky_star;

typedef struct orr_sky_psf {
    orr_image_kernel kernel; /* the PSF, normalised to 1, row 0 at the top */
    float *padded;           /* the same with ORR_SKY_PSF_PAD zeros around it, for sampling without bounds */
    int padded_width, padded_height;
    int exact;               /* tests: map every stamp pixel to the sky exactly (no tile interpolation) */
    double rad_per_pixel;    /* the angle on the sky of one PSF pixel */
    double reach_pixels;     /* the PSF's light lies within this many PSF pixels of its centre */
    int max_stars;           /* psf.spike_stars */
    double min_flux;         /* psf.spike_min_flux: relative to the brightest star */
    double spike_flux;       /* psf.spike_flux: and none of less flux than this (0: no such bound) */
    int key_plane;           /* the plane that says how bright a star is */
    orr_sky_star *lane[ORR_SKY_PSF_LANES]; /* per lane: the brightest so far, a min-heap */
    int nlane[ORR_SKY_PSF_LANES];
    orr_sky_star *stars; /* after orr_sky_psf_select: the brightest, brightest first */
    int nstars;
    int stars_drawn; /* after orr_sky_psf_draw: how many stars got the whole PSF */
} orr_sky_psf;

/* The FWHM of a PSF's core in PSF pixels: that of the pixel-integrated
 * Gaussian with the same (normalised) centre pixel value. */
orr_status orr_psf_core_fwhm(const orr_image_kernel *psf, double *fwhm_pixels, orr_error *err);

/* Takes psf (normalised; the caller's copy is moved into sp); its core is
 * drawn core_fwhm_rad wide on the sky, which sets the PSF's angular scale.
 * key_plane: 1 with colour (Y), 0 otherwise. */
orr_status orr_sky_psf_init(orr_sky_psf *sp, orr_image_kernel *psf, double core_fwhm_rad, int max_stars,
                            double min_flux, int key_plane, orr_error *err);
void orr_sky_psf_free(orr_sky_psf *sp);
/* Forgets the last frame's stars (the lanes' lists, the selection, the
 * count drawn): the renderer's plan keeps sp for a whole run, and each
 * frame collects its own stars. */
void orr_sky_psf_begin_frame(orr_sky_psf *sp);

/* Keeps the brightest visible particles of a deposited block (b as given
 * to orr_sph_deposit, w[k] the weights of plane k) in the lane's list.
 * Lanes are independent: one thread per lane. */
void orr_sky_psf_collect(orr_sky_psf *sp, int lane, const orr_sph_block *b, const float *const *w, int nplanes);

/* After the splat: the brightest of every lane's stars, in a fixed order
 * (the same whatever the threads). */
orr_status orr_sky_psf_select(orr_sky_psf *sp, orr_error *err);

/* With several processes (each having selected its own): every process
 * gets the brightest of all of them. A collective call. */
orr_status orr_sky_psf_share(orr_sky_psf *sp, const orr_parallel *par, orr_error *err);

/* Draws the whole PSF for the selected stars into planes, which hold every
 * star's core (the sum of all processes' planes). sph is the deposit that
 * drew the cores. */
orr_status orr_sky_psf_draw(orr_sky_psf *sp, const orr_sph *sph, orr_plane *planes, int nplanes, orr_error *err);

#endif
