/* Dome profiles (domes/NAME.yaml): the field of view, tilt and master size of
 * a planetarium dome, named by camera.dome (internal to src/scene). */
#ifndef ORR_SCENE_SCENE_DOME_H
#define ORR_SCENE_SCENE_DOME_H

#include "scene/scene_bind.h"

/* When camera.dome is set, finds and reads the profile (an error when it is
 * missing or bad, whatever the projection) and, for camera.projection: dome,
 * takes camera.dome_fov, camera.dome_tilt, image.width and image.height from
 * it unless the scene (marks) sets them. The search order: each folder of
 * $ORRERY_DOMES (colon-separated), <scene folder>/../domes,
 * <scene folder>/domes, then ORRERY_DOMES_DIR when compiled in. */
orr_status scene_apply_dome_profile(orr_scene *s, const scene_marks *m, orr_error *err);

#endif
