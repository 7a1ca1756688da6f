/* A Hubble-like (or FITS) PSF on a flat view, drawn star by star
 * (psf.kind hst or file with psf.fwhm; docs/psf.md, "Bright stars on flat
 * views").
 *
 * Convolving a crowded star field with the whole PSF at its own scale
 * (0.04" a pixel, a core 1.4 pixels wide) buries the bright stars' spikes:
 * every faint star's wings add to a haze as bright as the spikes, and a
 * spike within a few core widths of its star is lost in the star's own
 * rings. So, as on sky maps (post/sky_psf.h), the PSF is split by star:
 *
 *   - every star is drawn as the PSF's core: the splatted plane is
 *     convolved with a Gaussian of FWHM psf.fwhm pixels, all of a faint
 *     star's light staying in its core;
 *   - the brightest stars (psf.spike_stars, none fainter than
 *     psf.spike_min_flux of the brightest) are first taken out of the
 *     plane (their deposit repeated with the opposite weight), and after
 *     the core convolution the whole PSF is stamped in their place,
 *     magnified so that its core is psf.fwhm pixels wide too, and scaled
 *     to the star's flux.
 *
 * The stars are collected during the splat by the sky PSF's machinery
 * (orr_sky_psf_collect, _select, _share), whose rad_per_pixel then holds
 * image pixels per PSF pixel. */
#ifndef ORR_POST_FLAT_PSF_H
#define ORR_POST_FLAT_PSF_H

#include "post/convolve.h"
#include "post/sky_psf.h"
#include "splat/deposit.h"
#include "splat/sph.h"

/* Prepares the bright-star list for a flat view: psf (normalised) is moved
 * into sp, magnified so its core is core_fwhm_pixels wide. */
orr_status orr_flat_psf_init(orr_sky_psf *sp, orr_image_kernel *psf, double core_fwhm_pixels, int max_stars,
                             double min_flux, int key_plane, orr_error *err);

/* How a view deposited its particles, so a star's deposit can be undone:
 * a point deposit of this kind, or (sph not NULL) the SPH deposit. */
typedef struct orr_flat_deposit {
    orr_deposit_kind kind;
    const orr_projection *proj;
    const orr_sph *sph;
} orr_flat_deposit;

/* Draws the PSF into planes holding the splat (every process's sum): takes
 * the selected stars out, convolves every plane with core, and stamps the
 * whole PSF for each of those stars. */
orr_status orr_flat_psf_draw(orr_sky_psf *sp, const orr_flat_deposit *dep, orr_convolver *core,
                             orr_plane *planes, int nplanes, orr_error *err);

#endif
