/* A scene: everything a render needs, read from a YAML file and overridden
 * from the command line (--set key=value). Every key is listed, with its type,
 * default and meaning, in docs/scenes.md; unknown keys and wrong types are
 * errors naming the file, line and key. */
#ifndef ORR_SCENE_SCENE_H
#define ORR_SCENE_SCENE_H

#include <stdint.h>

#include "core/error.h"
#include "core/vecmath.h"
#include "frame/projection.h"
#include "post/colormap.h"
#include "post/stretch.h"
#include "source/source.h"
#include "splat/deposit.h"

#define ORR_NAME_MAX 128

typedef struct orr_scene {
    char path[ORR_PATH_MAX]; /* the scene file, for messages ("<built-in>" when none) */
    char dir[ORR_PATH_MAX];  /* its folder: relative paths in the scene are resolved against it */

    /* input.* */
    char input_file[ORR_PATH_MAX]; /* input.file, resolved; empty when a model is used */
    char input_format[32];         /* input.format: auto | text (default auto) */
    char model_name[32];           /* input.model.name: "mw-m31"; empty when a file is used */
    long long model_particles;     /* input.model.particles (default 200000) */
    uint64_t model_seed;           /* input.model.seed (default 1) */
    double model_separation;       /* input.model.separation, kpc (default 780) */
    char weight[ORR_FIELD_NAME_MAX]; /* input.weight: "mass" or a field name (default mass) */
    unsigned type_mask;            /* input.types: list of types 0..5 to draw; bit t set (default all, 0x3f) */
    long long chunk_size;          /* input.chunk: particles per chunk (default 1048576) */
    int skip_nonfinite;            /* input.nonfinite: error (0, default) | skip (1) */

    /* camera.* : exactly one of look_at, direction, quaternion orients it;
     * none means looking along -z with +y up (the xy plane face-on). */
    orr_vec3 camera_position;      /* camera.position (default 0,0,0 for ortho) */
    int has_look_at, has_direction, has_quaternion, has_up;
    orr_vec3 camera_look_at;       /* camera.look_at */
    orr_vec3 camera_direction;     /* camera.direction */
    orr_vec3 camera_up;            /* camera.up (default 0,1,0) */
    double camera_roll;            /* camera.roll, degrees (default 0) */
    orr_quat camera_quaternion;    /* camera.quaternion: [w, x, y, z] */

    /* camera.projection, camera.width, camera.fov, camera.near and image.* */
    orr_projection projection;     /* camera.projection (orthographic | perspective),
                                    * camera.width (ortho, default 100),
                                    * camera.fov (perspective, degrees, default 60),
                                    * camera.near (default 1e-3),
                                    * image.width, image.height (default 1024 x 1024) */
    orr_deposit_kind deposit;      /* deposit: ngp | cic (default cic) */

    /* output.* */
    char out_dir[ORR_PATH_MAX];    /* output.dir, resolved against the current directory (default ".") */
    char out_name[ORR_NAME_MAX];   /* output.name: base file name (default: the scene file's stem) */
    int write_fits;                /* output.fits (default true) */
    int write_png;                 /* output.png (default true) */
    int png_bits;                  /* output.png_bits: 8 | 16 (default 8) */
    orr_stretch stretch;           /* output.stretch: linear | log | asinh (default log),
                                    * output.white: number > 0 or "auto" (default auto),
                                    * output.white_percentile (default 99.9),
                                    * output.softening: n of log/asinh (default 1000) */
    orr_colormap_kind colormap;    /* output.colormap: grey | magma | inferno (default magma) */
    char bunit[ORR_NAME_MAX];      /* output.bunit: FITS BUNIT (default "mass/pixel") */
} orr_scene;

/* Fills s with the defaults above. */
void orr_scene_defaults(orr_scene *s);

/* Reads a scene file, then applies the overrides ("key=value", value in YAML
 * flow syntax, e.g. "camera.position=[0,0,10]") in order, then validates.
 * Errors name the file and line (or the --set argument) and the key. */
orr_status orr_scene_load(orr_scene *s, const char *path, const char *const *overrides, int noverrides,
                          orr_error *err);

/* The same from YAML text in memory (origin names it in messages), with
 * relative paths resolved against base_dir. Used for the built-in scenes and
 * by tests. */
orr_status orr_scene_load_string(orr_scene *s, const char *yaml, const char *origin, const char *base_dir,
                                 const char *const *overrides, int noverrides, orr_error *err);

#endif
