/* The observer frame of an observer-centred sky ("Future Sky"): one particle
 * is the observer, another the reference direction. Each frame:
 *   z = n0, the disc normal (fixed for a run);
 *   x = the observer-to-reference direction with its n0 component removed;
 *   y = z x x.
 * So the reference stays on the central meridian (l = 0) and moves along it
 * as the observer leaves the plane. Longitude l and latitude b are measured
 * in this frame, as galactic coordinates are. */
#ifndef ORR_FRAME_OBSERVER_H
#define ORR_FRAME_OBSERVER_H

#include <stdint.h>

#include "core/cards.h"
#include "core/error.h"
#include "core/keys.h"
#include "core/names.h"
#include "core/vecmath.h"
#include "frame/camera.h"

/* observer.*: an observer-centred sky. When observer.id is set the camera
 * sits on that particle, which is not drawn, and the frame is rebuilt every
 * frame: z = the disc normal n0, x = the direction to the reference
 * particle with its n0 component removed, y = z x x. camera.position and
 * the camera orientation keys are then not allowed. */
typedef struct orr_observer_settings {
    int has_id;            /* observer.id was given */
    uint64_t id;           /* observer.id */
    uint64_t reference_id; /* observer.reference_id (required with observer.id) */
    int has_normal;
    orr_vec3 normal;       /* observer.normal: n0 (default [0, 0, 1]) */
    unsigned normal_types; /* observer.normal_from.types: compute n0 from the angular momentum of
                            * these types (bit mask; 0 = use observer.normal) */
    double normal_radius;  /* observer.normal_from.radius: ... within this distance of the
                            * reference particle (default 30) */
    int normal_sign;       /* observer.normal_from.sign: +1 | -1 (default -1: galactic north is
                            * opposite the Milky Way's spin) */
    int dim;               /* observer.dim: weights fall off as 1/r^2 from the observer (default true) */
    double dim_near;       /* observer.dim_near: r below this counts as this (default 0.01) */
} orr_observer_settings;

/* The words of observer.normal_from.sign ("1" is read as +1 too). */
extern const orr_named orr_normal_sign_names[];

/* Fills d with the defaults above. */
void orr_observer_settings_defaults(orr_observer_settings *d);

/* The observer.* keys checked against each other: with observer.id its
 * reference particle (another one), the normal given or computed, not
 * both; without, none of its keys; keys says which were given, and where. */
orr_status orr_observer_prepare(const orr_observer_settings *o, const orr_keys *keys, orr_error *err);

/* An observer's cards (OBSID, REFID, DIMMED and the disc normal NORMX..Z,
 * which each frame gives: reserved); none without observer.id. */
void orr_observer_cards(const orr_observer_settings *o, orr_cards *h);

typedef struct orr_sky_frame {
    orr_vec3 origin;  /* the observer's position (the world origin without an observer) */
    orr_vec3 x, y, z; /* unit axes: x toward l = 0, y toward l = 90, z toward b = 90 */
} orr_sky_frame;

/* The frame from the observer and reference positions and the normal n0.
 * Fails when the two positions coincide or the reference lies along n0. */
orr_status orr_sky_frame_build(orr_sky_frame *f, orr_vec3 observer, orr_vec3 reference, orr_vec3 n0,
                               orr_error *err);

/* The world axes as a sky frame: l = 0 along +x, b = 90 along +z. */
orr_sky_frame orr_sky_frame_world(orr_vec3 origin);

/* The world direction of (l, b) in degrees. */
orr_vec3 orr_sky_direction(const orr_sky_frame *f, double l_deg, double b_deg);

/* (l, b) in degrees of a world direction (l in (-180, 180]). */
void orr_sky_lb(const orr_sky_frame *f, orr_vec3 dir, double *l_deg, double *b_deg);

/* A camera at the frame's origin looking at (l, b) = (0, 0) with north up,
 * then rolled: the orientation of full-sky maps and flat views from the
 * observer. */
orr_status orr_sky_camera_centre(orr_camera *cam, const orr_sky_frame *f, double roll_deg, orr_error *err);

/* A dome camera: the dome's zenith toward `zenith` (l, b), the front toward
 * `front` (projected perpendicular to the zenith), then the zenith pitched
 * toward the front by tilt_deg. */
orr_status orr_sky_camera_dome(orr_camera *cam, const orr_sky_frame *f, const double zenith_lb[2],
                               const double front_lb[2], double tilt_deg, orr_error *err);

#endif
