/* Stereo cameras: where each eye sits and how its picture is projected.
 * docs/stereo.md has the method and its limits.
 *
 * Perspective: two parallel cameras offset by -/+ separation/2 along the
 * camera's right axis, each with its image shifted horizontally (an
 * off-axis frustum) so that a point on the view axis at the convergence
 * distance lands on the same pixel in both eyes. Nearer points have crossed
 * (negative) parallax: further right in the left eye's image than in the
 * right eye's. Unlike toed-in cameras this adds no vertical parallax.
 *
 * Omni-directional stereo (ODS) for the sky projections (dome,
 * equirectangular, hammer-aitoff): every viewing direction has its own eye
 * on a circle of radius separation/2 in the horizontal plane (perpendicular
 * to the dome's zenith, or to the map's pole), offset to the left or right
 * of the horizontal viewing direction. A particle at p is seen by the eye e
 * on that circle whose tangent ray passes through p, so the renderer
 * projects p - e instead of p (orr_stereo_ods_apply, per block). */
#ifndef ORR_FRAME_STEREO_H
#define ORR_FRAME_STEREO_H

#include <stddef.h>
#include <stdint.h>

#include "core/error.h"
#include "core/keys.h"
#include "core/names.h"
#include "frame/camera.h"
#include "frame/projection.h"

typedef enum {
    ORR_STEREO_NONE,
    ORR_STEREO_ANAGLYPH,     /* NAME.png: a red-cyan anaglyph; NAME.fits: both eyes */
    ORR_STEREO_SIDE_BY_SIDE, /* one picture, left eye on the left */
    ORR_STEREO_OVER_UNDER,   /* one picture, left eye on top (the VR top-bottom convention) */
    ORR_STEREO_SEPARATE,     /* NAME-left.EXT and NAME-right.EXT */
} orr_stereo_mode;

#define ORR_EYE_LEFT (-1)
#define ORR_EYE_RIGHT 1

extern const orr_named orr_stereo_mode_names[];
const char *orr_stereo_mode_name(orr_stereo_mode mode);
/* 1 and *mode set when name is none, anaglyph, side-by-side, over-under or separate. */
int orr_stereo_mode_from_name(const char *name, orr_stereo_mode *mode);
/* "left" or "right". */
const char *orr_eye_name(int eye);

/* stereo.*: stereo pairs (perspective) and omni-directional stereo (sky
 * maps); docs/stereo.md. How the two pictures become one (stereo.anaglyph)
 * is the post stage's (post/picture.h). */
typedef struct orr_stereo_settings {
    orr_stereo_mode mode;  /* stereo.mode: none | anaglyph | side-by-side | over-under | separate
                            * (default none) */
    double eye_separation; /* stereo.eye_separation: interocular distance, scene units (> 0;
                            * required with a stereo mode) */
    double convergence;    /* stereo.convergence: distance of the zero-parallax plane,
                            * perspective only (default auto, stored as 0: the distance from the
                            * camera to camera.look_at, taken when the frame is rendered, so a
                            * moving camera keeps converging on its target) */
    double zenith_fade;    /* stereo.zenith_fade: degrees from the pole over which an ODS eye
                            * separation falls to zero (0..90, default 0: no fade) */
    int eye;               /* not a key: 0, or ORR_EYE_LEFT / ORR_EYE_RIGHT in the copy of the
                            * scene the renderer makes for each eye (render/plan.c) */
} orr_stereo_settings;

/* Fills d with the defaults above. */
void orr_stereo_settings_defaults(orr_stereo_settings *d);

/* The stereo.* keys checked against each other and the projection (kind):
 * a pair needs parallax and an eye separation; its anaglyph, zenith fade
 * and convergence keys only with the mode or projection they are for;
 * without a pair, none of its keys. keys says which were given, and where. */
orr_status orr_stereo_prepare(const orr_stereo_settings *st, orr_projection_kind kind, const orr_keys *keys,
                              orr_error *err);

/* A stereo view's cards (STEREO, EYE or EYES, EYESEP; a pair's CONVERG,
 * which each frame gives: reserved, or ODS's ZENFADE); the anaglyph's
 * is the picture's (orr_picture_stereo_cards). */
void orr_stereo_cards(const orr_stereo_settings *st, orr_projection_kind kind, orr_cards *h);

/* Moves a perspective camera to one eye (ORR_EYE_LEFT or ORR_EYE_RIGHT):
 * its position by eye * separation / 2 along its right axis, and the
 * projection's principal point by eye * focal * separation / (2 convergence)
 * pixels. proj must be a planned perspective projection; it is planned
 * again from its settings with that shift. Fails when separation or
 * convergence is not a positive number. */
orr_status orr_stereo_perspective_eye(orr_camera *cam, orr_projection *proj, int eye, double separation,
                                      double convergence, orr_error *err);

/* One eye of omni-directional stereo, for the per-block transform. */
typedef struct orr_stereo_ods {
    int eye;              /* ORR_EYE_LEFT or ORR_EYE_RIGHT */
    int side;             /* the side of the viewing direction the eye is on, -1 left, +1 right,
                           * in the camera frame: the eye itself, except on a map drawn mirrored
                           * (camera.lon_flip), where the opposite eye keeps the depth right */
    int pole_is_z;        /* the dome: its zenith is the view direction (+z); the horizontal
                           * plane is x, y. Sky maps: the pole is "up" (-y); the plane is x, z */
    float radius;         /* separation / 2 */
    float inv_sin_fade;   /* 1 / sin(zenith_fade); 0 when there is no fade */
} orr_stereo_ods;

/* Sets up one eye of ODS for a sky projection. A mirrored map (lon_flip,
 * "outside looking in") mirrors parallax too, which would turn depth
 * inside out; the eyes swap sides in the camera frame so that in the
 * picture near things still stand out. zenith_fade_deg (0 to 90,
 * 0 = none) is the angle from the pole over which the separation falls to
 * zero: separation * min(1, sin(angle from the pole) / sin(fade)).
 * Fails for a projection that is not a sky map or a bad separation. */
orr_status orr_stereo_ods_setup(orr_stereo_ods *ods, const orr_projection *proj, int eye, double separation,
                                double zenith_fade_deg, orr_error *err);

/* Moves n camera-frame points (x, y, z) to their positions relative to the
 * ODS eye that sees them. Points inside the eye circle (horizontal distance
 * below the radius) cannot be seen correctly by any eye on it: keep[i] is 0
 * for them (1 for the others), their coordinates are left as they were, and
 * the count of them is returned. The arrays must not overlap. */
size_t orr_stereo_ods_apply(const orr_stereo_ods *ods, size_t n, float *x, float *y, float *z, uint8_t *keep);
/* visible[i] &= keep[i]: the particles inside an ODS eye circle are not drawn. */
void orr_stereo_mask(size_t n, uint8_t *visible, const uint8_t *keep);

#endif
