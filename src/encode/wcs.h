/* FITS world coordinates, so DS9 and astropy read longitude and latitude (in
 * the observer frame, GLON/GLAT: galactic coordinates for "Future Sky"; else
 * the scene's own axes, WDLN/WDLT) straight off the image: Hammer-Aitoff as
 * -AIT, equirectangular as -CAR, dome masters as zenithal equidistant -ARC
 * with CRVAL at the zenith, perspective frames as gnomonic -TAN about the view
 * direction; orthographic views get linear axes in scene lengths. Conventions: Calabretta & Greisen 2002, A&A 395,
 * 1077 (FITS WCS paper II). */
#ifndef ORR_ENCODE_WCS_H
#define ORR_ENCODE_WCS_H

#include "encode/fits.h"
#include "frame/camera.h"
#include "frame/observer.h"
#include "frame/projection.h"

/* What the WCS of one view is made from. */
typedef struct orr_wcs_view {
    const orr_projection *proj;
    const orr_camera *camera;
    const orr_sky_frame *frame; /* the longitude/latitude frame of the sky maps */
    int observer_frame;         /* frame is an observer's (GLON/GLAT), not the scene's axes (WDLN/WDLT) */
    const char *length_unit;    /* orthographic: the FITS unit of scene lengths, or "" when unknown */
} orr_wcs_view;

/* Adds the WCS cards for a view to h: -AIT, -CAR, -ARC (dome), -TAN
 * (perspective) or linear (orthographic). Returns 1 when it did; 0 when the
 * view has no standard WCS (a Hammer-Aitoff or equirectangular map whose
 * centre is off the equator or whose up is not north, which these
 * projections cannot describe without a rotation). */
int orr_wcs_add_cards(orr_cards *h, const orr_wcs_view *view);

/* A frame's header begun from its view's planned cards: planned (each
 * stage's cards, with the places of the values each frame gives reserved)
 * copied into frame and this frame's world coordinates added
 * (orr_wcs_add_cards); the caller then sets the reserved values. */
void orr_wcs_frame_cards(orr_cards *frame, const orr_cards *planned, const orr_wcs_view *view);

/* A HEALPix map's COORDSYS: "G" when its (theta, phi) are the observer
 * frame's (90 - b, l), i.e. an observer defines the frame and the camera is
 * centred on l = b = 0 with north up (the default with an observer); NULL
 * otherwise (the scene's or the camera's own axes, which HEALPix has no
 * name for). */
const char *orr_wcs_healpix_coordsys(const orr_wcs_view *view);

#endif
