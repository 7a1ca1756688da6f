/* A view's point spread function (psf.*). A flat view convolves its plane
 * with the PSF after splatting (FFT, post/convolve.h). A sky map's pixel
 * scale varies across it (a dome master's tangential scale is theta/sin theta
 * times its radial one), so one pixel kernel cannot give stars the same
 * angular size everywhere; there each particle is drawn instead as an SPH
 * kernel whose half-maximum width on the sky is the PSF's (core's) FWHM
 * (and a particle that has a smoothing length of its own as both, added in
 * quadrature), and with psf.kind hst or file the brightest stars are then
 * redrawn with the whole PSF in angle (post/sky_psf.h). A flat view given
 * psf.fwhm with an hst or file PSF draws its stars the same way, in pixels
 * (post/flat_psf.h). docs/psf.md. */
#ifndef ORR_POST_VIEW_PSF_H
#define ORR_POST_VIEW_PSF_H

#include "frame/projection.h"
#include "post/convolve.h"
#include "post/flat_psf.h"
#include "post/psf.h"
#include "post/sky_psf.h"
#include "splat/kernel.h"

/* The automatic core of a sky map's PSF (psf.fwhm_arcmin: auto): this many
 * pixels across at half maximum, at the map's centre. A star drawn as a
 * kernel this wide keeps its flux and its centroid wherever it falls (the
 * kernel is integrated over each pixel), and the share of its flux in its
 * brightest pixel varies by at most 1.2x over the sub-pixel positions
 * (tests/cli/check_star_shimmer.py): 1.39x at 2 pixels, 1.23x at 2.8, 1.19x
 * at 3.2. Narrower cores are sharper and twinkle as stars move. */
#define ORR_SKY_CORE_PIXELS 3.2

typedef struct orr_view_psf {
    orr_convolver *conv; /* flat views: the convolution; NULL for none (or stars drawn one by one) */
    orr_convolver *core; /* flat views with hst/file and psf.fwhm: every star's core (post/flat_psf.h) */
    double h_per_r;      /* sky maps: kernel h per unit distance giving the PSF's FWHM; 0 for none */
    double core_fwhm_arcmin; /* sky maps: that FWHM, psf.fwhm_arcmin's or the automatic one */
    orr_sky_psf *sky;    /* sky maps with an hst or file PSF, and flat views with core: the bright stars'
                          * whole PSF; else NULL */
    /* What the cards say (orr_view_psf_cards), from the settings and the map. */
    orr_psf_kind kind;       /* psf.kind */
    int on_sky;              /* made for a sky map */
    double fwhm;             /* psf.fwhm: a flat view's FWHM (or its stars' core's), pixels */
    double arcsec_per_pixel; /* psf.arcsec_per_pixel: an hst or file PSF's image scale */
} orr_view_psf;

/* The Hubble PSF kernels a plan has made (render/plan.h), each with the
 * psf.* settings it was made from, so that the views of a run that ask for
 * the same one share it and it is made once per run. Zero-initialise. */
#define ORR_PSF_KERNELS_MAX 16
typedef struct orr_psf_kernel_memo {
    double angle, arcsec_per_pixel, vane_width, spike_gain;
    int size;
    orr_image_kernel kernel;
} orr_psf_kernel_memo;
typedef struct orr_psf_kernels {
    int n;
    orr_psf_kernel_memo kernel[ORR_PSF_KERNELS_MAX];
} orr_psf_kernels;
void orr_psf_kernels_free(orr_psf_kernels *memo);

/* Prepares the PSF of settings ps for a projection that has been set up;
 * colour: the planes are X, Y, Z (stars are ranked by Y); k is the kernel
 * sky maps draw with; memo (or NULL) the plan's kernels. Made once per
 * run: it depends on the settings and the image, never on the frame. */
orr_status orr_view_psf_setup(orr_view_psf *vp, const orr_psf_settings *ps, int colour, const orr_projection *proj,
                              const orr_kernel *k, orr_psf_kernels *memo, orr_error *err);
/* The PSF as an image kernel (psf.kind hst or file), normalised, with its
 * angular scale; a Hubble PSF from memo when it holds it (memo may be NULL). */
orr_status orr_view_psf_kernel(const orr_psf_settings *ps, orr_psf_kernels *memo, orr_image_kernel *out,
                               orr_error *err);
/* Convolves a flat view's plane (nothing for a sky map or no PSF). */
orr_status orr_view_psf_apply(orr_view_psf *vp, orr_plane *plane, orr_error *err);
void orr_view_psf_free(orr_view_psf *vp);

/* The PSF's cards: PSF (its kind) and its width (PSFFWHM or PSFSCALE); with
 * stars drawn one by one, the core's width, the whole PSF's scale (PSFMAG
 * or PSFSKYSC) and the stars drawn so (PSFSTARS, which each frame gives:
 * reserved). */
void orr_view_psf_cards(const orr_view_psf *vp, orr_cards *h);

/* The radius q (in units of h) where the kernel's column density falls to
 * half its central value. */
double orr_kernel_half_max_q(const orr_kernel *k);

#endif
