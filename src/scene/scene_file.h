/* Reading scene and dome profile files, and the path helpers the loaders
 * share (internal to src/scene). */
#ifndef ORR_SCENE_SCENE_FILE_H
#define ORR_SCENE_SCENE_FILE_H

#include <stddef.h>

#include "core/error.h"

/* Reads a whole text file into a NUL-terminated buffer the caller frees.
 * what names the kind of file in messages ("scene file", "dome profile"). A
 * file that cannot be opened or read is ORR_ERR_IO; one too large or with a
 * NUL byte is ORR_ERR_USAGE. */
orr_status scene_read_text(const char *path, const char *what, char **out, orr_error *err);

/* The file name without folder and extension: "scenes/face-on.yaml" -> "face-on". */
void scene_path_stem(const char *path, char *out, size_t size);

/* The folder part of path: "a/b/scene.yaml" -> "a/b", "scene.yaml" -> ".". */
void scene_path_dir(const char *path, char *out, size_t size);

#endif
