/* Sizes shared by every stage. */
#ifndef ORR_CORE_LIMITS_H
#define ORR_CORE_LIMITS_H

/* Longest path a file name may have, terminator included (Linux PATH_MAX). */
#define ORR_PATH_MAX 4096

/* Longest short name (an output name, a unit, a dome profile), terminator included. */
#define ORR_NAME_MAX 128

/* Longest text of a scene's effective settings, or of the scene as YAML,
 * terminator included (orr_scene.settings, .scene_yaml). */
#define ORR_SETTINGS_MAX 16384

#endif
