/* The metadata a rendered view's pictures and planes carry in the formats
 * other than FITS (OpenEXR, OpenImageIO's; docs/formats-out.md): the
 * scene's name, the projection with the parameters orrery alone defines
 * (and for a perspective view OpenEXR's screen window), the simulation
 * time, the camera, and what the picture shows. (FITS files get the
 * view's cards, encode/fits.h.) */
#ifndef ORR_ENCODE_VIEW_META_H
#define ORR_ENCODE_VIEW_META_H

#include "encode/image_out.h"
#include "frame/camera.h"
#include "frame/projection.h"

/* Strings the metadata borrows besides the caller's. */
typedef struct orr_view_meta_text {
    char number[32];
} orr_view_meta_text;

/* The metadata of a view named name (borrowed, as desc and t are) in
 * projection p, at simulation time `time`, seen by cam. */
orr_image_meta orr_view_image_meta(const char *name, const orr_projection *p, double time, const orr_camera *cam,
                                   const char *desc, orr_view_meta_text *t);

#endif
