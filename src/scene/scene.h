/* A scene: everything a render needs, read from a YAML file and overridden
 * from the command line (--set key=value). Every key is listed, with its type,
 * default and meaning, in docs/scenes.md; unknown keys and wrong types are
 * errors naming the file, line and key. */
#ifndef ORR_SCENE_SCENE_H
#define ORR_SCENE_SCENE_H

#include <stdint.h>

#include "core/error.h"
#include "core/vecmath.h"
#include "dust/dust.h"
#include "frame/path.h"
#include "frame/projection.h"
#include "frame/stereo.h"
#include "particles/population.h"
#include "particles/smoothing.h"
#include "post/anaglyph.h"
#include "post/colormap.h"
#include "post/colour.h"
#include "post/psf.h"
#include "post/stretch.h"
#include "source/sequence.h"
#include "source/source.h"
#include "splat/deposit.h"
#include "splat/kernel.h"

#define ORR_NAME_MAX 128
#define ORR_SETTINGS_MAX 16384

/* Room for input.sequence.files: at most this many paths, in this many
 * bytes together (a pattern has no such limit). */
#define ORR_SEQ_FILES_MAX 1024
#define ORR_SEQ_FILES_BYTES 32768

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
    int model_galaxies;            /* input.model.galaxies: ORR_MODEL_PAIR (default), _MW, _M31 */
    double model_disc_q;           /* input.model.disc_q: the discs' Toomre Q (default 1.5) */
    double model_w0;               /* input.model.w0: king's central potential W0 (default 7) */
    double model_core_radius;      /* input.model.core_radius: king's r0, pc (default 1) */
    double model_mass;             /* input.model.mass: king's total mass, Msun (default 5e5) */
    long long model_dust_particles; /* input.model.dust_particles: mw-m31's dusty gas discs, type 0,
                                    * appended after the other particles (default 0: none) */
    char weight[ORR_FIELD_NAME_MAX]; /* input.weight: "mass" or a field name (default mass) */
    unsigned type_mask;            /* input.types: list of types 0..5 to draw; bit t set (default all, 0x3f) */
    long long chunk_size;          /* input.chunk: particles per chunk (default 1048576) */
    int skip_nonfinite;            /* input.nonfinite: error (0, default) | skip (1) */
    /* input.periodic.* : a periodic box drawn replicated (docs/periodic.md). */
    double periodic_box;           /* input.periodic.box: the box side (0 = auto: the file's BoxSize) */
    int periodic_replicas;         /* input.periodic.replicas: copies per axis, odd (default 1 = off) */
    int periodic_around_camera;    /* input.periodic.centre: camera (1, default) | origin (0) */
    double periodic_radius;        /* input.periodic.radius: centre camera draws the images within it
                                    * (0 = auto: (replicas - 1) / 2 box sides) */
    double periodic_fade;          /* input.periodic.fade: the width of the taper inside the radius */
    int has_periodic_fade;         /* ... given (else a quarter of the radius) */
    int insitu;                    /* input.insitu: the particles come from a running simulation
                                    * through orrery.h, which sets it; input.file and input.model.*
                                    * are then optional and unused (default false) */

    /* input.sequence.* : snapshots interpolated in time (docs/sequences.md),
     * instead of input.file; listed by a pattern and a range, or by files. */
    char seq_pattern[ORR_PATH_MAX];  /* input.sequence.pattern: "snap_%03d.hdf5", resolved; empty when none */
    long long seq_first;             /* input.sequence.first (default 0) */
    long long seq_last;              /* input.sequence.last (required with a pattern) */
    long long seq_step;              /* input.sequence.step (default 1) */
    int seq_nfiles;                  /* input.sequence.files: how many (0 when none) */
    char seq_files[ORR_SEQ_FILES_BYTES]; /* ...the paths, resolved, one after another, each ending in NUL;
                                      * read them with orr_scene_sequence_file */
    orr_interpolation seq_interpolation; /* input.sequence.interpolation: auto | linear | hermite (default auto) */
    double seq_max_memory;           /* input.sequence.max_memory: GiB two resident snapshots may take
                                      * (default 16) */

    /* camera.* : exactly one of look_at, direction, quaternion orients it;
     * none means looking along -z with +y up (the xy plane face-on). */
    orr_vec3 camera_position;      /* camera.position (default 0,0,0 for ortho) */
    int has_look_at, has_direction, has_quaternion, has_up;
    orr_vec3 camera_look_at;       /* camera.look_at */
    orr_vec3 camera_direction;     /* camera.direction */
    orr_vec3 camera_up;            /* camera.up (default 0,1,0) */
    double camera_roll;            /* camera.roll, degrees (default 0) */
    orr_quat camera_quaternion;    /* camera.quaternion: [w, x, y, z] */

    /* camera.path.* : a camera that moves over an animation (docs/paths.md).
     * The path places and orients the camera in every frame, so camera.position
     * and the orientation keys are not allowed with it (except with kind
     * rotate, whose start they are), nor is observer.id. The renderer asks
     * orr_path_camera(&s->camera_path, frame_time, ...) for each frame. */
    int has_path;                  /* camera.path.kind was given */
    orr_camera_path camera_path;   /* camera.path.kind: keyframes | orbit | line | inspiral | rotate,
                                    * and the keys of each kind */
    char path_file[ORR_PATH_MAX];  /* camera.path.file: keyframes from CSV, resolved */
    int has_path_start;
    orr_vec3 path_start;           /* camera.path.start: an orbit's first point */

    /* camera.projection, camera.width, camera.fov, camera.near and image.* */
    orr_projection projection;     /* camera.projection (orthographic | perspective),
                                    * camera.width (ortho, default 100),
                                    * camera.fov (perspective, degrees, default 60),
                                    * camera.near (default 1e-3),
                                    * image.width, image.height (default 1024 x 1024) */
    orr_deposit_kind deposit;      /* deposit: ngp | cic | sph (default cic) */

    /* smoothing.* : the SPH kernel deposit (deposit: sph) */
    orr_kernel_kind kernel;        /* smoothing.kernel: cubic | wendland-c2 | wendland-c4 (default cubic) */
    orr_smoothing_source lengths;  /* smoothing.lengths: auto | file | neighbours (default auto: the
                                    * file's when it has them, else from the neighbours) */
    int neighbours;                /* smoothing.neighbours: k of the k-th nearest neighbour (default 32) */
    double h_scale;                /* smoothing.h_scale: multiplies every smoothing length (default 1) */

    /* Sky projections (camera.projection: hammer-aitoff | dome | equirectangular).
     * projection.lon_flip:     camera.lon_flip (bool, default false)
     * projection.dome_fov_deg: camera.dome_fov (90..360; default from the dome profile, else 180) */
    char dome_profile[ORR_NAME_MAX]; /* camera.dome: a profile name from domes/ (default none) */
    double dome_tilt;              /* camera.dome_tilt, degrees 0..90 (default from the profile, else 0):
                                    * the dome's zenith is pitched toward its front by this angle */
    int has_zenith, has_front;
    double zenith_lb[2];           /* camera.zenith: [l, b] degrees in the observer frame: the
                                    * direction at the dome's zenith before tilting (default [0, 90]) */
    double front_lb[2];            /* camera.front: [l, b] degrees: the direction drawn toward the
                                    * bottom of the dome master (default [0, 0]) */

    /* colour.* : true colours (docs/colour.md). With colour.populations the
     * render splats CIE X, Y and Z planes (written to FITS, linear) and the
     * PNG is their colour synthesis; without, one weight plane and a colour
     * map. */
    int colour;                    /* colour.populations was given */
    orr_population_set populations;/* colour.populations: list of {name, select, colour, luminance} */
    uint64_t colour_seed;          /* colour.seed: of the populations' random draws (default 1) */
    char colour_only[ORR_POPULATION_NAME_MAX]; /* colour.only: draw just this population (default: all);
                                    * the others still take their particles first, so separate renders
                                    * of each population add up to the render of all */
    int only;                      /* its index, -1 for all */
    orr_colour_synth synth;        /* colour.synthesis.stretch: linear | log | gamma | asinh (default log),
                                    * .softening (10), .gamma (0.5), .white (auto), .white_percentile (99.9),
                                    * .brightness (1), .contrast (1), .clip: desaturate | channel | none */

    /* compose.layers: `orrery compose` blends raw planes of several renders
     * (e.g. one per population, or single-channel maps of different
     * particle types) with colours assigned there, then synthesises. */
    int nlayers;
    struct orr_compose_layer {
        char file[ORR_PATH_MAX];   /* a raw FITS file: one luminance plane, or X, Y, Z */
        int has_colour;
        orr_colour colour;         /* required for a luminance plane */
        double gain;               /* multiplies the layer (default 1) */
    } layers[8];

    /* colour.tint.* : a single-channel map (no populations) drawn in one
     * colour, taken along a path of blackbody temperatures (e.g. a hue from
     * blue to deep red over a run) instead of a colour map. */
    int has_tint;                  /* colour.tint.path was given */
    orr_colour_path tint;          /* colour.tint.path: list of temperatures, K */
    double tint_t;                 /* colour.tint.t: position along it, 0..1 (default 0) */
    int tint_run;                  /* colour.tint.t: run: the position is the frame's u in the run
                                    * (0 at the first frame, 1 at the last) instead of tint_t */
    int png_linear;                /* output.png_transfer: srgb (0, default) | linear (1): the transfer
                                    * curve of colour PNGs (colour maps are sRGB by definition) */

    /* psf.* : a point spread function. Flat views convolve the splatted
     * plane with it (FFT); sky maps, whose scale varies across the image,
     * draw each particle as a kernel of the PSF core's angular size instead,
     * and the brightest stars with the whole PSF (render/sky_psf.h).
     * docs/psf.md. */
    orr_psf_kind psf;              /* psf.kind: none | gaussian | hst | file (default none) */
    double psf_fwhm;               /* psf.fwhm: Gaussian FWHM in pixels, flat views (default 2) */
    double psf_fwhm_arcmin;        /* psf.fwhm_arcmin: FWHM in arcminutes on sky maps (0: auto, ORR_SKY_CORE_PIXELS
                                    * pixels at the map's centre), of the Gaussian or of
                                    * the hst/file PSF's core, which scales the whole PSF (default 10) */
    char psf_file[ORR_PATH_MAX];   /* psf.file: a FITS PSF image (psf.kind: file) */
    int psf_file_subsample;        /* psf.file_subsample: file pixels per detector pixel (default 1) */
    double psf_arcsec_per_pixel;   /* psf.arcsec_per_pixel: the image's pixel scale for hst and file PSFs
                                    * (default 0.04, near Hubble ACS/WFC; 0 for a file: its own pixels) */
    double psf_angle;              /* psf.angle: direction of the spikes, degrees (default 45) */
    double psf_vane_width;         /* psf.vane_width: hst, the vanes' full width over the primary's radius
                                    * (default 0.022, Hubble's); wider vanes, brighter and shorter spikes */
    double psf_spike_gain;         /* psf.spike_gain: hst, the spikes' light beyond the core times this, the PSF
                                    * renormalised (default 1: as diffraction makes them; an artist's choice) */
    int psf_size;                  /* psf.size: odd kernel side in pixels (default 129) */
    int psf_spike_stars;           /* psf.spike_stars: sky maps, hst/file: at most this many of the brightest
                                    * stars are drawn with the whole PSF, the others as its core (default 200) */
    int psf_flat_stars;            /* a flat view with psf.kind hst or file and psf.fwhm: stars drawn as the core,
                                    * the brightest with the whole PSF (render/flat_psf.h); set by the check */
    double psf_spike_min_flux;     /* psf.spike_min_flux: and none fainter than this fraction of the
                                    * brightest star (default 0.001) */
    int has_glow;
    double glow_threshold;         /* glow.threshold: sky maps: stars of less flux at the camera are drawn as
                                    * kernels as wide as the angle to their smoothing.neighbours-th nearest
                                    * star on the sky, brighter ones as the PSF's core (default: no glow) */
    double glow_max_arcmin;        /* glow.max_arcmin: ... and so are stars whose kernel would be wider than
                                    * this, where stars are sparse on the sky (default 60) */

    /* observer.* : an observer-centred sky. When observer.id is set the camera
     * sits on that particle, which is not drawn, and the frame is rebuilt every
     * frame: z = the disc normal n0, x = the direction to the reference
     * particle with its n0 component removed, y = z x x. camera.position and
     * the camera orientation keys are then not allowed. */
    int has_observer;              /* observer.id was given */
    uint64_t observer_id;          /* observer.id */
    uint64_t reference_id;         /* observer.reference_id (required with observer.id) */
    int has_normal;
    orr_vec3 observer_normal;      /* observer.normal: n0 (default [0, 0, 1]) */
    unsigned normal_types;         /* observer.normal_from.types: compute n0 from the angular momentum of
                                    * these types (bit mask; 0 = use observer.normal) */
    double normal_radius;          /* observer.normal_from.radius: ... within this distance of the
                                    * reference particle (default 30) */
    int normal_sign;               /* observer.normal_from.sign: +1 | -1 (default -1: galactic north is
                                    * opposite the Milky Way's spin) */
    int dim;                       /* observer.dim: weights fall off as 1/r^2 from the observer (default true) */
    double dim_near;               /* observer.dim_near: r below this counts as this (default 0.01) */
    int camera_dim;                /* camera.dim: weights fall off as 1/r^2 from the camera (default false) */
    double camera_dim_near;        /* camera.dim_near: r below this counts as this (default 0.01) */

    /* dust.* : extinction and reddening by dust particles (docs/dust.md);
     * the settings belong to the dust stage (dust/dust.h). */
    orr_dust_settings dust;

    /* animation.* : a run of frames (docs/animation.md). Shared by every view. */
    long long anim_frames;         /* animation.frames: frames in the run (default 1: a still) */
    double anim_fps;               /* animation.fps: frames per second of the film (default 30) */
    int white_smoothing;           /* animation.white_smoothing: frames over which the automatic white level
                                    * is averaged, so it follows the scene without flicker (default 0: each
                                    * frame its own); render/animation.h orr_animation_smooth_whites */
    double shutter;                /* animation.shutter: the share of the frame interval the shutter is open,
                                    * each particle drawn as its streak over it (default 0: no motion blur);
                                    * render/motion_blur.h */
    int has_frame_interval;
    double frame_interval;         /* animation.frame_interval: simulation time between frames, which the
                                    * shutter moves particles over (default: from animation.time) */
    int has_anim_time;
    double anim_time[2];           /* animation.time: [t0, t1], the simulation time at the first and the
                                    * last frame, linear in between (default: a sequence's first and last
                                    * snapshot; a single snapshot's own time) */

    /* stereo.* : stereo pairs (perspective) and omni-directional stereo
     * (sky maps); docs/stereo.md. */
    orr_stereo_mode stereo;        /* stereo.mode: none | anaglyph | side-by-side | over-under | separate
                                    * (default none) */
    double eye_separation;         /* stereo.eye_separation: interocular distance, scene units (> 0;
                                    * required with a stereo mode) */
    double convergence;            /* stereo.convergence: distance of the zero-parallax plane,
                                    * perspective only (default auto, stored as 0: the distance from the
                                    * camera to camera.look_at, taken when the frame is rendered, so a
                                    * moving camera keeps converging on its target) */
    orr_anaglyph_kind anaglyph;    /* stereo.anaglyph: grey | colour | dubois (default dubois) */
    double zenith_fade;            /* stereo.zenith_fade: degrees from the pole over which an ODS eye
                                    * separation falls to zero (0..90, default 0: no fade) */
    int stereo_eye;                /* not a key: 0, or ORR_EYE_LEFT / ORR_EYE_RIGHT in the copy of the
                                    * scene the renderer makes for each eye (render/stereo_view.h) */

    /* output.* */
    char out_dir[ORR_PATH_MAX];    /* output.dir, resolved against the current directory (default ".") */
    char out_name[ORR_NAME_MAX];   /* output.name: base file name (default: the scene file's stem) */
    int write_fits;                /* output.fits (default true) */
    int write_png;                 /* output.png (default true) */
    int write_exr;                 /* output.exr: also NAME.exr, the linear planes as float OpenEXR
                                    * (default false) */
    int exr_half;                  /* output.exr_half: that file's samples as half floats (default false) */
    int exr_population_layers;     /* output.exr_population_layers: each colour population's Y kept as a
                                    * plane of its own and written as layer pop.NAME.Y (default false) */
    int fits_compress;             /* output.fits_compress: orr_fits_compression of NAME.fits (default none) */
    char image_ext[16];            /* output.image: also the picture as NAME.EXT in this format, e.g.
                                    * tif, jpg, exr (by OpenImageIO; default none) */
    int write_raw;                 /* output.raw: also NAME.raw.fits, the planes before the PSF, for
                                    * `orrery compose` (default false) */
    int png_bits;                  /* output.png_bits: 8 | 16 (default 8) */
    orr_stretch stretch;           /* output.stretch: linear | log | asinh (default log),
                                    * output.white: number > 0 or "auto" (default auto),
                                    * output.white_percentile (default 99.9),
                                    * output.softening: n of log/asinh (default 1000) */
    orr_colormap_kind colormap;    /* output.colormap: grey | magma | inferno (default magma) */
    char bunit[ORR_NAME_MAX];      /* output.bunit: the FITS unit of a particle's weight (default "": the
                                    * model's, else unknown, scene_output.h); the planes' BUNIT is it per
                                    * steradian or per area (post/brightness.h) */
    char length_unit[ORR_NAME_MAX]; /* output.length_unit: the FITS unit of scene lengths (default "": kpc
                                     * for the model, else unknown) */
    long long frame_start;         /* output.frame_start: the number of a run's first frame (default 0) */
    int frame_digits;              /* output.frame_digits: at least this many digits (default 4) */
    char frame_separator[8];       /* output.frame_separator: between NAME and the number (default "_") */
    int alpha_mask;                /* output.alpha_mask: pictures as RGBA, transparent off the map */

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

/* Fills s with the defaults above. */
void orr_scene_defaults(orr_scene *s);

/* Whether the scene's input is a sequence (input.sequence.pattern or .files). */
int orr_scene_has_sequence(const orr_scene *s);

/* The point the camera keeps looking at, where there is one: camera.look_at,
 * an orbit's centre, an inspiral's target, a line's look_at. A stereo pair
 * converges there by default. Returns 0 when there is none. */
int orr_scene_look_target(const orr_scene *s, orr_vec3 *target);

/* The camera of camera.position and its orientation keys (quaternion,
 * look_at, direction with up or roll; none: looking along -z with +y up),
 * ignoring any path: a still's camera, and where a rotate path starts. */
orr_status orr_scene_static_camera(const orr_scene *s, orr_camera *cam, orr_error *err);
/* Path i (0 <= i < s->seq_nfiles) of input.sequence.files. */
const char *orr_scene_sequence_file(const orr_scene *s, int i);

/* Reads a scene file, then applies the overrides ("key=value", value in YAML
 * flow syntax, e.g. "camera.position=[0,0,10]") in order, then validates.
 * Errors name the file and line (or the --set argument) and the key. A file
 * with `views:` gives its view when it has exactly one, and is an error
 * when it has several (load those with orr_scene_load_views). */
orr_status orr_scene_load(orr_scene *s, const char *path, const char *const *overrides, int noverrides,
                          orr_error *err);

/* Loads every view of a scene file (one, unnamed, when it has no `views:`).
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
