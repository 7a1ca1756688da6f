/* A scene: everything a render needs, read from a YAML file and overridden
 * from the command line (--set key=value). Every key is listed, with its type,
 * default and meaning, in docs/scenes.md; unknown keys and wrong types are
 * errors naming the file, line and key. */
#ifndef ORR_SCENE_SCENE_H
#define ORR_SCENE_SCENE_H

#include <stdint.h>

#include "core/error.h"
#include "core/limits.h"
#include "core/vecmath.h"
#include "dust/dust.h"
#include "encode/output_settings.h"
#include "frame/camera_settings.h"
#include "frame/observer.h"
#include "frame/projection.h"
#include "frame/replicas.h"
#include "frame/stereo.h"
#include "post/colour.h"
#include "post/picture.h"
#include "scene/compose_settings.h"
#include "post/psf.h"
#include "source/settings.h"
#include "stars/stars.h"
#include "splat/deposit.h"

/* animation.*: a run of frames (docs/animation.md), shared by every view.
 * The render stage drives runs, and it comes after the scene, so the scene
 * keeps these settings itself. */
typedef struct orr_animation_settings {
    long long frames;       /* animation.frames: frames in the run (default 1: a still) */
    double fps;             /* animation.fps: frames per second of the film (default 30) */
    int white_smoothing;    /* animation.white_smoothing: frames over which the automatic white level
                             * is averaged, so it follows the scene without flicker (default 0: each
                             * frame its own); render/animation.h orr_animation_smooth_whites */
    double shutter;         /* animation.shutter: the share of the frame interval the shutter is open,
                             * each particle drawn as its streak over it (default 0: no motion blur);
                             * pass/motion_blur.h */
    int has_frame_interval;
    double frame_interval;  /* animation.frame_interval: simulation time between frames, which the
                             * shutter moves particles over (default: from animation.time) */
    int has_time;
    double time[2];         /* animation.time: [t0, t1], the simulation time at the first and the
                             * last frame, linear in between (default: a sequence's first and last
                             * snapshot; a single snapshot's own time) */
} orr_animation_settings;

/* A scene is the settings of every stage, each stage's in a struct of its
 * own that the stage declares and gives defaults to (docs/architecture.md
 * has the table of stages, structs and keys); the scene binds the YAML keys
 * into them (scene_bind.c) and checks the keys against each other
 * (scene_check.c). */
typedef struct orr_scene {
    /* The scene's strings (these two, and the file and folder names in the
     * stages' settings) are owned heap strings (core/owned.h): a scene is
     * freed with orr_scene_free and copied with orr_scene_copy, never by
     * assignment alone. */
    char *path; /* the scene file, for messages ("<built-in>" when none) */
    char *dir;  /* its folder: relative paths in the scene are resolved against it */

    orr_input_settings input;       /* source: input.* (source/settings.h) */
    orr_periodic_settings periodic; /* frame: input.periodic.* (frame/replicas.h) */
    orr_camera_settings camera;     /* frame: camera.* orientation, path, dome, dim (frame/camera_settings.h) */
    orr_projection_settings projection; /* frame: camera.projection, .width, .fov, .near, .lon_flip,
                                         * .healpix_*, .dome_fov; image.width, .height (frame/projection.h) */
    orr_observer_settings observer; /* frame: observer.* (frame/observer.h) */
    orr_stereo_settings stereo;     /* frame: stereo.* but anaglyph (frame/stereo.h) */
    orr_deposit_settings deposit;   /* splat: deposit, smoothing.* (splat/deposit.h) */
    orr_stars_settings stars;       /* stars: stars.* (stars/stars.h) */
    orr_dust_settings dust;         /* dust: dust.* (dust/dust.h) */
    orr_colour_settings colour;     /* post: colour.* (post/colour.h) */
    orr_psf_settings psf;           /* post: psf.*, glow.* (post/psf.h) */
    orr_picture_settings picture;   /* post: output.stretch, .white, .white_percentile, .softening,
                                     * .colormap; stereo.anaglyph (post/picture.h) */
    orr_output_settings output;     /* encode: the other output.* (encode/output_settings.h) */
    orr_animation_settings animation; /* animation.* (above) */
    orr_compose_settings compose;   /* compose.layers (above) */

    /* Not keys: what the scene says, for frame markers (render/animation.c),
     * which redo a frame made with other settings. The effective keys after
     * overrides and merging a view, one "key=value" line each in document
     * order (yt_settings_text), then the dome profile's values; cut short
     * when longer than the buffer, but the digest covers the whole text. */
    char settings[ORR_SETTINGS_MAX];
    uint64_t settings_digest;
    /* Not a key: the same effective keys as a YAML document that renders
     * this view again (yt_yaml_text, after a comment naming the folder its
     * relative file names are relative to), stored in the FITS outputs as
     * their SCENE extension; "" when longer than the buffer. */
    char scene_yaml[ORR_SETTINGS_MAX];
    int regrade_final;             /* not a key: a compose re-grades NAME.fits, the planes after the PSF
                                    * (the white-smoothing pass), rather than NAME.raw.fits */
} orr_scene;

/* A scene file may hold several views of the same particles (a dome master
 * and a panorama, say) under `views:`, a mapping from view name to the keys
 * that view changes; each view is the scene with those keys merged in. */
#define ORR_SCENE_MAX_VIEWS 8

typedef struct orr_scene_views {
    int n;
    orr_scene view[ORR_SCENE_MAX_VIEWS];
    char name[ORR_SCENE_MAX_VIEWS][ORR_NAME_MAX]; /* "" for a scene without views */
} orr_scene_views;

/* Fills s, which holds no strings (zeroed or freed), with the defaults
 * above; its path, folder and output.dir are allocated, so free s with
 * orr_scene_free even when this fails (out of memory). */
orr_status orr_scene_defaults(orr_scene *s, orr_error *err);

/* Frees the scene's strings (a zeroed scene holds none), leaving them NULL. */
void orr_scene_free(orr_scene *s);

/* dst (its strings freed first; zeroed or a scene) becomes a copy of src
 * with strings of its own. */
orr_status orr_scene_copy(orr_scene *dst, const orr_scene *src, orr_error *err);

/* Sets output.dir to dir (the command line's -o), a string of s's own. */
orr_status orr_scene_set_output_dir(orr_scene *s, const char *dir, orr_error *err);

/* Frees the strings of views->view[0..n) and sets n to 0. */
void orr_scene_views_free(orr_scene_views *views);

/* Whether the scene's input is a sequence (input.sequence.pattern or .files). */
int orr_scene_has_sequence(const orr_scene *s);

/* Whether the scene's shutter moves the particles by their velocities, so
 * that the renderer must read vx, vy, vz (scene_sequence.c). */
int orr_scene_blur_moves_particles(const orr_scene *s);

/* The point the camera keeps looking at, where there is one
 * (orr_camera_settings_look_target, frame/camera_settings.h). */
int orr_scene_look_target(const orr_scene *s, orr_vec3 *target);

/* The camera of camera.position and its orientation keys, ignoring any
 * path (orr_camera_settings_static, frame/camera_settings.h). */
orr_status orr_scene_static_camera(const orr_scene *s, orr_camera *cam, orr_error *err);
/* Path i (0 <= i < s->input.sequence.nfiles) of input.sequence.files. */
const char *orr_scene_sequence_file(const orr_scene *s, int i);

/* Reads a scene file, then applies the overrides ("key=value", value in YAML
 * flow syntax, e.g. "camera.position=[0,0,10]") in order, then validates.
 * s is overwritten: it must hold no strings (zeroed, or freed with
 * orr_scene_free); free it with orr_scene_free after, failed or not.
 * Errors name the file and line (or the --set argument) and the key. A file
 * with `views:` gives its view when it has exactly one, and is an error
 * when it has several (load those with orr_scene_load_views). */
orr_status orr_scene_load(orr_scene *s, const char *path, const char *const *overrides, int noverrides,
                          orr_error *err);

/* Loads every view of a scene file (one, unnamed, when it has no `views:`).
 * out is overwritten (it must hold no strings); on success free it with
 * orr_scene_views_free; a failed load frees what it made.
 * Overrides apply to the scene before the views are merged in, so a view's
 * own keys win; "views.NAME.KEY=VALUE" overrides one view. Views may not
 * change input.* or observer.*: all views are rendered from one pass over
 * the particles. */
orr_status orr_scene_load_views(orr_scene_views *out, const char *path, const char *const *overrides,
                                int noverrides, orr_error *err);

/* The same from YAML text in memory (origin names it in messages), with
 * relative paths resolved against base_dir. Used for the built-in scenes and
 * by tests. */
orr_status orr_scene_load_string(orr_scene *s, const char *yaml, const char *origin, const char *base_dir,
                                 const char *const *overrides, int noverrides, orr_error *err);

/* orr_scene_load_views from YAML text in memory, as orr_scene_load_string. */
orr_status orr_scene_load_views_string(orr_scene_views *out, const char *yaml, const char *origin,
                                       const char *base_dir, const char *const *overrides, int noverrides,
                                       orr_error *err);

#endif
