/* FITS world coordinates for sky maps, so DS9 and astropy read longitude and
 * latitude (in the observer frame: galactic coordinates for "Future Sky")
 * straight off the image: Hammer-Aitoff as GLON-AIT/GLAT-AIT,
 * equirectangular as -CAR, dome masters as zenithal equidistant -ARC with
 * CRVAL at the zenith. Conventions: Calabretta & Greisen 2002, A&A 395,
 * 1077 (FITS WCS paper II). */
#ifndef ORR_RENDER_WCS_H
#define ORR_RENDER_WCS_H

#include "encode/fits.h"
#include "frame/camera.h"
#include "frame/observer.h"
#include "frame/projection.h"

/* Adds the WCS cards for a sky map to h. Returns 1 when it did; 0 when the
 * map has no standard WCS (not a sky projection, or an Hammer-Aitoff or
 * equirectangular map whose centre is off the equator or whose up is not
 * north, which these projections cannot describe without a rotation). */
int orr_wcs_add_cards(orr_fits_header *h, const orr_projection *p, const orr_camera *cam,
                      const orr_sky_frame *frame);

#endif
