#include "scene/scene_bind.h"
#include "core/numbers.h"

#include "scene/scene_colour.h"
#include "scene/scene_sequence.h"
#include "scene/scene_path.h"
#include "source/models/model.h"
#include "source/source.h"

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

/* ---- the table of keys ---- */

typedef enum {
    K_STRING,   /* any non-empty text */
    K_FILENAME, /* non-empty text without '/' */
    K_PATH,     /* a file path, resolved against the scene's folder */
    K_NUMBER,   /* double, finite, within the bounds */
    K_AUTO,     /* double within the bounds, or the word auto (stored as 0) */
    K_RUN,      /* double within the bounds, or the word run (stored as 0, sets the has_* flag) */
    K_INT,      /* int within ilo..ihi */
    K_LLONG,    /* long long within ilo..ihi */
    K_U64,      /* uint64_t within ilo..ihi (ilo >= 0) */
    K_BOOL,     /* int 0 / 1 */
    K_ENUM,     /* a word that parse_word accepts */
    K_NAMED,    /* a word of an orr_named table, its value stored in an int-sized field */
    K_VEC3,     /* orr_vec3 from [x, y, z] */
    K_QUAT,     /* orr_quat from [w, x, y, z] */
    K_TYPES,    /* unsigned bit mask from a list of particle types 0..5 */
    K_POPULATIONS, /* colour.populations: a list of mappings (scene_colour.c) */
    K_TINT,        /* colour.tint.path: a list of temperatures (scene_colour.c) */
    K_LAYERS,      /* compose.layers: a list of mappings (scene_colour.c) */
    K_SEQ_FILES,   /* input.sequence.files: a list of paths (scene_sequence.c) */
    K_ID,       /* uint64_t, the full range: a particle id */
    K_LB,       /* double[2] from [l, b], degrees: l any finite number, b in [-90, 90] */
    K_PAIR,     /* double[2] from [a, b], any finite numbers */
    K_KEYFRAMES, /* camera.path.keyframes: a list of mappings (scene_path.c) */
} key_type;

/* Bounds of K_NUMBER, K_AUTO and K_RUN. */
enum {
    HAS_LO = 1,
    LO_OPEN = 2, /* the bound itself is excluded */
    HAS_HI = 4,
    HI_OPEN = 8,
};

typedef struct key_spec {
    const char *key;
    key_type type;
    size_t offset, size;          /* the field in the target (orr_scene or dome_profile) */
    double lo, hi;                /* K_NUMBER, K_AUTO, K_RUN: with the bounds flags */
    unsigned bounds;
    long long ilo, ihi;           /* integers: inclusive range */
    int (*parse_word)(orr_scene *s, const char *word); /* K_ENUM: 1 when accepted (scene keys only) */
    const char *(*choices)(void); /* K_ENUM: the accepted words, for messages */
    const char *choices_note;     /* K_ENUM: more words, told after the value ("sky maps: ...") */
    const orr_named *names;       /* K_NAMED: the stage's table of words and values */
    int has_flag;                 /* a has_* flag to set when the key is present */
    size_t flag_offset;
} key_spec;

#define FIELD_OF(type, m) .offset = offsetof(type, m), .size = sizeof(((type *)0)->m)
#define FLAG_OF(type, m) .has_flag = 1, .flag_offset = offsetof(type, m)
#define FIELD(m) FIELD_OF(orr_scene, m)
#define FLAG(m) FLAG_OF(orr_scene, m)
/* K_RUN: the int field set to 1 for the word run, 0 for a number. */
#define RUN_FLAG(m) .flag_offset = offsetof(orr_scene, m)
#define IRANGE(a, b) .ilo = (a), .ihi = (b)
#define ABOVE(a) .lo = (a), .bounds = HAS_LO | LO_OPEN
#define CLOSED(a, b) .lo = (a), .hi = (b), .bounds = HAS_LO | HAS_HI

/* Words of the scene's own switches, for K_NAMED (the stages' enumerations
 * have their tables in their own headers). */
static const orr_named NONFINITE_NAMES[] = {{"error", 0}, {"skip", 1}, {NULL, 0}};
static const orr_named PERIODIC_CENTRE_NAMES[] = {{"camera", 1}, {"origin", 0}, {NULL, 0}};
static const orr_named HEALPIX_ORDER_NAMES[] = {{"ring", 0}, {"nested", 1}, {NULL, 0}};
static const orr_named PNG_TRANSFER_NAMES[] = {{"srgb", 0}, {"linear", 1}, {NULL, 0}};
static const orr_named PNG_BITS_NAMES[] = {{"8", 8}, {"16", 16}, {NULL, 0}};
/* The values of orr_fits_compression (encode/fits.h). */
static const orr_named FITS_COMPRESS_NAMES[] = {{"none", 0}, {"gzip", 1}, {NULL, 0}};

/* Word parsers for the enumerated keys that need more than a table. */
static int word_input_format(orr_scene *s, const char *w)
{
    if (strcmp(w, "auto") != 0 && !orr_source_format_known(w))
        return 0;
    snprintf(s->input_format, sizeof s->input_format, "%s", w);
    return 1;
}
static const char *names_input_format(void)
{
    static char names[128];
    snprintf(names, sizeof names, "auto %s", orr_source_format_names());
    return names;
}

static int word_model_name(orr_scene *s, const char *w)
{
    if (strcmp(w, "mw-m31") != 0 && strcmp(w, "king") != 0)
        return 0;
    snprintf(s->model_name, sizeof s->model_name, "%s", w);
    return 1;
}
static const char *names_model_name(void) { return "mw-m31 king"; }

/* input.model.galaxies: model.h's ORR_MODEL_PAIR, _MW, _M31 (0, 1, 2). */
static int word_model_galaxies(orr_scene *s, const char *w)
{
    int g = orr_model_galaxies_named(w);
    s->model_galaxies = g >= 0 ? g : s->model_galaxies;
    return g >= 0;
}
static const char *names_model_galaxies(void) { return "pair mw m31"; }

static int word_projection(orr_scene *s, const char *w)
{
    static const orr_projection_kind kinds[] = {ORR_PROJ_ORTHOGRAPHIC, ORR_PROJ_PERSPECTIVE,
                                                ORR_PROJ_HAMMER_AITOFF, ORR_PROJ_DOME,
                                                ORR_PROJ_EQUIRECTANGULAR, ORR_PROJ_HEALPIX};
    for (size_t i = 0; i < sizeof kinds / sizeof kinds[0]; i++) {
        if (strcmp(w, orr_projection_name(kinds[i])) == 0) {
            s->projection.kind = kinds[i];
            return 1;
        }
    }
    return 0;
}
/* The flat projections are listed first and the sky maps in a note after
 * the value, which keeps the message of a mistyped flat one as it was. */
static const char *names_projection(void) { return "orthographic perspective"; }
#define SKY_PROJECTIONS "sky maps: hammer-aitoff dome equirectangular healpix"

static int word_normal_sign(orr_scene *s, const char *w)
{
    if (strcmp(w, "1") == 0 || strcmp(w, "+1") == 0)
        s->normal_sign = 1;
    else if (strcmp(w, "-1") == 0)
        s->normal_sign = -1;
    else
        return 0;
    return 1;
}
static const char *names_normal_sign(void) { return "+1 -1"; }

static int word_colormap(orr_scene *s, const char *w) { return orr_colormap_from_name(w, &s->colormap); }

#define ENUM(fn) .type = K_ENUM, .parse_word = word_##fn, .choices = names_##fn
/* The field must be int-sized: the table's value is stored as an int. */
#define NAMED(table, m) .type = K_NAMED, .names = (table), FIELD(m)

static const key_spec KEYS[] = {
    {.key = "input.file", .type = K_PATH, FIELD(input_file)},
    {.key = "input.format", ENUM(input_format)},
    {.key = "input.model.name", ENUM(model_name)},
    {.key = "input.model.particles", .type = K_LLONG, FIELD(model_particles), IRANGE(100, 2000000000LL)},
    {.key = "input.model.seed", .type = K_U64, FIELD(model_seed), IRANGE(0, LLONG_MAX)},
    {.key = "input.model.separation", .type = K_NUMBER, FIELD(model_separation), ABOVE(0)},
    {.key = "input.model.galaxies", ENUM(model_galaxies)},
    {.key = "input.model.disc_q", .type = K_NUMBER, FIELD(model_disc_q), ABOVE(0)},
    {.key = "input.model.w0", .type = K_NUMBER, FIELD(model_w0), CLOSED(0.5, 15)},
    {.key = "input.model.core_radius", .type = K_NUMBER, FIELD(model_core_radius), ABOVE(0)},
    {.key = "input.model.mass", .type = K_NUMBER, FIELD(model_mass), ABOVE(0)},
    {.key = "input.model.dust_particles", .type = K_LLONG, FIELD(model_dust_particles), IRANGE(0, 2000000000LL)},
    {.key = "input.weight", .type = K_STRING, FIELD(weight)},
    {.key = "input.types", .type = K_TYPES, FIELD(type_mask)},
    {.key = "input.chunk", .type = K_LLONG, FIELD(chunk_size), IRANGE(1, 4294967296LL)},
    {.key = "input.nonfinite", NAMED(NONFINITE_NAMES, skip_nonfinite)},
    {.key = "input.periodic.box", .type = K_AUTO, FIELD(periodic_box), ABOVE(0)},
    {.key = "input.periodic.replicas", .type = K_INT, FIELD(periodic_replicas), IRANGE(1, 9)},
    {.key = "input.periodic.centre", NAMED(PERIODIC_CENTRE_NAMES, periodic_around_camera)},
    {.key = "input.periodic.radius", .type = K_AUTO, FIELD(periodic_radius), ABOVE(0)},
    {.key = "input.periodic.fade", .type = K_NUMBER, FIELD(periodic_fade), .lo = 0, .bounds = HAS_LO,
     FLAG(has_periodic_fade)},
    {.key = "input.insitu", .type = K_BOOL, FIELD(insitu)},
    {.key = "input.sequence.pattern", .type = K_PATH, FIELD(seq_pattern)},
    {.key = "input.sequence.first", .type = K_LLONG, FIELD(seq_first), IRANGE(0, 1000000000LL)},
    {.key = "input.sequence.last", .type = K_LLONG, FIELD(seq_last), IRANGE(0, 1000000000LL)},
    {.key = "input.sequence.step", .type = K_LLONG, FIELD(seq_step), IRANGE(1, 1000000000LL)},
    {.key = "input.sequence.files", .type = K_SEQ_FILES},
    {.key = "input.sequence.interpolation", NAMED(orr_interpolation_names, seq_interpolation)},
    {.key = "input.sequence.max_memory", .type = K_NUMBER, FIELD(seq_max_memory), ABOVE(0)},
    {.key = "camera.position", .type = K_VEC3, FIELD(camera_position)},
    {.key = "camera.look_at", .type = K_VEC3, FIELD(camera_look_at), FLAG(has_look_at)},
    {.key = "camera.direction", .type = K_VEC3, FIELD(camera_direction), FLAG(has_direction)},
    {.key = "camera.up", .type = K_VEC3, FIELD(camera_up), FLAG(has_up)},
    {.key = "camera.roll", .type = K_NUMBER, FIELD(camera_roll)},
    {.key = "camera.quaternion", .type = K_QUAT, FIELD(camera_quaternion), FLAG(has_quaternion)},
    {.key = "camera.path.kind", NAMED(orr_path_kind_names, camera_path.kind), FLAG(has_path)},
    {.key = "camera.path.keyframes", .type = K_KEYFRAMES},
    {.key = "camera.path.file", .type = K_PATH, FIELD(path_file)},
    {.key = "camera.path.interpolation", NAMED(orr_path_interp_names, camera_path.interpolation)},
    {.key = "camera.path.orientation", NAMED(orr_path_orient_names, camera_path.orientation)},
    {.key = "camera.path.ease", NAMED(orr_ease_names, camera_path.ease)},
    {.key = "camera.path.centre", .type = K_VEC3, FIELD(camera_path.centre)},
    {.key = "camera.path.target", .type = K_VEC3, FIELD(camera_path.centre)},
    {.key = "camera.path.axis", .type = K_VEC3, FIELD(camera_path.axis)},
    {.key = "camera.path.radius", .type = K_NUMBER, FIELD(camera_path.radius), ABOVE(0)},
    {.key = "camera.path.start", .type = K_VEC3, FIELD(path_start), FLAG(has_path_start)},
    {.key = "camera.path.start_angle", .type = K_NUMBER, FIELD(camera_path.start_angle)},
    {.key = "camera.path.turns", .type = K_NUMBER, FIELD(camera_path.turns)},
    {.key = "camera.path.r0", .type = K_NUMBER, FIELD(camera_path.r0), ABOVE(0)},
    {.key = "camera.path.r1", .type = K_NUMBER, FIELD(camera_path.r1), ABOVE(0)},
    {.key = "camera.path.radial", NAMED(orr_radial_law_names, camera_path.radial)},
    {.key = "camera.path.from", .type = K_VEC3, FIELD(camera_path.from)},
    {.key = "camera.path.to", .type = K_VEC3, FIELD(camera_path.to)},
    {.key = "camera.path.look_at", .type = K_VEC3, FIELD(camera_path.look_at), FLAG(camera_path.has_look_at)},
    {.key = "camera.path.up", .type = K_VEC3, FIELD(camera_path.up)},
    {.key = "camera.path.angle", .type = K_NUMBER, FIELD(camera_path.angle)},
    {.key = "camera.projection", ENUM(projection), .choices_note = SKY_PROJECTIONS},
    {.key = "camera.width", .type = K_NUMBER, FIELD(projection.ortho_width), ABOVE(0)},
    {.key = "camera.fov", .type = K_NUMBER, FIELD(projection.fov_deg), .lo = 0, .hi = 180,
     .bounds = HAS_LO | LO_OPEN | HAS_HI | HI_OPEN},
    {.key = "camera.near", .type = K_NUMBER, FIELD(projection.near), .lo = 0, .bounds = HAS_LO},
    {.key = "camera.lon_flip", .type = K_BOOL, FIELD(projection.lon_flip)},
    {.key = "camera.healpix_nside", .type = K_INT, FIELD(projection.healpix_nside), IRANGE(1, ORR_HEALPIX_NSIDE_MAX)},
    {.key = "camera.healpix_order", NAMED(HEALPIX_ORDER_NAMES, projection.healpix_nested)},
    {.key = "camera.dome", .type = K_FILENAME, FIELD(dome_profile)},
    {.key = "camera.dome_fov", .type = K_NUMBER, FIELD(projection.dome_fov_deg), CLOSED(90, 360)},
    {.key = "camera.dome_tilt", .type = K_NUMBER, FIELD(dome_tilt), CLOSED(0, 90)},
    {.key = "camera.zenith", .type = K_LB, FIELD(zenith_lb), FLAG(has_zenith)},
    {.key = "camera.front", .type = K_LB, FIELD(front_lb), FLAG(has_front)},
    {.key = "image.width", .type = K_INT, FIELD(projection.width), IRANGE(1, ORR_IMAGE_SIDE_MAX)},
    {.key = "image.height", .type = K_INT, FIELD(projection.height), IRANGE(1, ORR_IMAGE_SIDE_MAX)},
    {.key = "deposit", NAMED(orr_deposit_names, deposit)},
    {.key = "smoothing.kernel", NAMED(orr_kernel_names, kernel)},
    {.key = "smoothing.lengths", NAMED(orr_smoothing_source_names, lengths)},
    {.key = "smoothing.neighbours", .type = K_INT, FIELD(neighbours), IRANGE(1, 4096)},
    {.key = "smoothing.h_scale", .type = K_NUMBER, FIELD(h_scale), ABOVE(0)},
    {.key = "colour.populations", .type = K_POPULATIONS},
    {.key = "colour.only", .type = K_STRING, FIELD(colour_only)},
    {.key = "colour.seed", .type = K_U64, FIELD(colour_seed), IRANGE(0, LLONG_MAX)},
    {.key = "colour.synthesis.stretch", NAMED(orr_lum_stretch_names, synth.stretch)},
    {.key = "colour.synthesis.softening", .type = K_NUMBER, FIELD(synth.n), ABOVE(0)},
    {.key = "colour.synthesis.gamma", .type = K_NUMBER, FIELD(synth.gamma), ABOVE(0)},
    {.key = "colour.synthesis.white", .type = K_AUTO, FIELD(synth.y0), ABOVE(0)},
    {.key = "colour.synthesis.white_percentile", .type = K_NUMBER, FIELD(synth.y0_percentile), .lo = 0, .hi = 100,
     .bounds = HAS_LO | LO_OPEN | HAS_HI},
    {.key = "colour.synthesis.brightness", .type = K_NUMBER, FIELD(synth.brightness), ABOVE(0)},
    {.key = "colour.synthesis.contrast", .type = K_NUMBER, FIELD(synth.contrast), ABOVE(0)},
    {.key = "colour.synthesis.clip", NAMED(orr_clip_names, synth.clip)},
    {.key = "colour.tint.path", .type = K_TINT},
    {.key = "compose.layers", .type = K_LAYERS},
    {.key = "colour.tint.t", .type = K_RUN, FIELD(tint_t), CLOSED(0, 1), RUN_FLAG(tint_run)},
    {.key = "psf.kind", NAMED(orr_psf_kind_names, psf)},
    {.key = "psf.fwhm", .type = K_NUMBER, FIELD(psf_fwhm), CLOSED(0.1, 1000)},
    {.key = "psf.fwhm_arcmin", .type = K_AUTO, FIELD(psf_fwhm_arcmin), CLOSED(0.01, 3000)},
    {.key = "psf.file", .type = K_PATH, FIELD(psf_file)},
    {.key = "psf.file_subsample", .type = K_INT, FIELD(psf_file_subsample), IRANGE(1, 64)},
    {.key = "psf.arcsec_per_pixel", .type = K_NUMBER, FIELD(psf_arcsec_per_pixel), .lo = 0, .bounds = HAS_LO},
    {.key = "psf.angle", .type = K_NUMBER, FIELD(psf_angle)},
    {.key = "psf.vane_width", .type = K_NUMBER, FIELD(psf_vane_width), CLOSED(0.001, 0.2)},
    {.key = "psf.spike_gain", .type = K_NUMBER, FIELD(psf_spike_gain), CLOSED(1, 1000)},
    {.key = "psf.size", .type = K_INT, FIELD(psf_size), IRANGE(3, 2047)},
    {.key = "psf.spike_stars", .type = K_INT, FIELD(psf_spike_stars), IRANGE(0, 100000)},
    {.key = "psf.spike_min_flux", .type = K_NUMBER, FIELD(psf_spike_min_flux), CLOSED(0, 1)},
    {.key = "glow.threshold", .type = K_NUMBER, FIELD(glow_threshold), .lo = 0, .bounds = HAS_LO,
     FLAG(has_glow)},
    {.key = "glow.max_arcmin", .type = K_NUMBER, FIELD(glow_max_arcmin), ABOVE(0)},
    {.key = "observer.id", .type = K_ID, FIELD(observer_id), FLAG(has_observer)},
    {.key = "observer.reference_id", .type = K_ID, FIELD(reference_id)},
    {.key = "observer.normal", .type = K_VEC3, FIELD(observer_normal), FLAG(has_normal)},
    {.key = "observer.normal_from.types", .type = K_TYPES, FIELD(normal_types)},
    {.key = "observer.normal_from.radius", .type = K_NUMBER, FIELD(normal_radius), ABOVE(0)},
    {.key = "observer.normal_from.sign", ENUM(normal_sign)},
    {.key = "observer.dim", .type = K_BOOL, FIELD(dim)},
    {.key = "observer.dim_near", .type = K_NUMBER, FIELD(dim_near), ABOVE(0)},
    {.key = "camera.dim", .type = K_BOOL, FIELD(camera_dim)},
    {.key = "camera.dim_near", .type = K_NUMBER, FIELD(camera_dim_near), ABOVE(0)},
    {.key = "dust.types", .type = K_TYPES, FIELD(dust.types)},
    {.key = "dust.kappa_v", .type = K_NUMBER, FIELD(dust.kappa_v), ABOVE(0)},
    {.key = "dust.dust_to_gas", .type = K_NUMBER, FIELD(dust.dust_to_gas), ABOVE(0)},
    {.key = "dust.metallicity", .type = K_STRING, FIELD(dust.metallicity)},
    {.key = "dust.z_sun", .type = K_NUMBER, FIELD(dust.z_sun), ABOVE(0)},
    {.key = "dust.curve", NAMED(orr_dust_curve_names, dust.curve)},
    {.key = "dust.r_v", .type = K_NUMBER, FIELD(dust.r_v), CLOSED(1, 10)},
    {.key = "dust.curve_file", .type = K_PATH, FIELD(dust.curve_file)},
    {.key = "dust.extinction_plane", .type = K_BOOL, FIELD(dust.extinction_plane)},
    {.key = "animation.frames", .type = K_LLONG, FIELD(anim_frames), IRANGE(1, 10000000)},
    {.key = "animation.fps", .type = K_NUMBER, FIELD(anim_fps), CLOSED(0.001, 1000)},
    {.key = "animation.white_smoothing", .type = K_INT, FIELD(white_smoothing), IRANGE(0, 100000)},
    {.key = "animation.time", .type = K_PAIR, FIELD(anim_time), FLAG(has_anim_time)},
    {.key = "animation.shutter", .type = K_NUMBER, FIELD(shutter), CLOSED(0, 1)},
    {.key = "animation.frame_interval", .type = K_NUMBER, FIELD(frame_interval), .lo = 0, .bounds = HAS_LO,
     FLAG(has_frame_interval)},

    {.key = "stereo.mode", NAMED(orr_stereo_mode_names, stereo)},
    {.key = "stereo.eye_separation", .type = K_NUMBER, FIELD(eye_separation), ABOVE(0)},
    {.key = "stereo.convergence", .type = K_AUTO, FIELD(convergence), ABOVE(0)},
    {.key = "stereo.anaglyph", NAMED(orr_anaglyph_names, anaglyph)},
    {.key = "stereo.zenith_fade", .type = K_NUMBER, FIELD(zenith_fade), CLOSED(0, 90)},
    {.key = "output.dir", .type = K_STRING, FIELD(out_dir)},
    {.key = "output.name", .type = K_FILENAME, FIELD(out_name)},
    {.key = "output.fits", .type = K_BOOL, FIELD(write_fits)},
    {.key = "output.png", .type = K_BOOL, FIELD(write_png)},
    {.key = "output.raw", .type = K_BOOL, FIELD(write_raw)},
    {.key = "output.png_transfer", NAMED(PNG_TRANSFER_NAMES, png_linear)},
    {.key = "output.exr", .type = K_BOOL, FIELD(write_exr)},
    {.key = "output.exr_half", .type = K_BOOL, FIELD(exr_half)},
    {.key = "output.exr_population_layers", .type = K_BOOL, FIELD(exr_population_layers)},
    {.key = "output.fits_compress", NAMED(FITS_COMPRESS_NAMES, fits_compress)},
    {.key = "output.image", .type = K_FILENAME, FIELD(image_ext)},
    {.key = "output.png_bits", NAMED(PNG_BITS_NAMES, png_bits)},
    {.key = "output.stretch", NAMED(orr_stretch_names, stretch.kind)},
    {.key = "output.white", .type = K_AUTO, FIELD(stretch.white), ABOVE(0)},
    {.key = "output.white_percentile", .type = K_NUMBER, FIELD(stretch.white_percentile), .lo = 0,
     .hi = 100, .bounds = HAS_LO | LO_OPEN | HAS_HI},
    {.key = "output.softening", .type = K_NUMBER, FIELD(stretch.n), ABOVE(0)},
    {.key = "output.colormap", .type = K_ENUM, .parse_word = word_colormap, .choices = orr_colormap_names},
    {.key = "output.bunit", .type = K_STRING, FIELD(bunit)},
    {.key = "output.length_unit", .type = K_STRING, FIELD(length_unit)},
    {.key = "output.frame_start", .type = K_LLONG, FIELD(frame_start), IRANGE(0, 1000000000LL)},
    {.key = "output.frame_digits", .type = K_INT, FIELD(frame_digits), IRANGE(1, 18)},
    {.key = "output.frame_separator", .type = K_STRING, FIELD(frame_separator)},
    {.key = "output.alpha_mask", .type = K_BOOL, FIELD(alpha_mask)},
};

/* The keys of a dome profile (domes/NAME.yaml). */
static const key_spec PROFILE_KEYS[] = {
    {.key = "description", .type = K_STRING, FIELD_OF(dome_profile, description)},
    {.key = "fov", .type = K_NUMBER, FIELD_OF(dome_profile, fov), CLOSED(90, 360), FLAG_OF(dome_profile, has_fov)},
    {.key = "tilt", .type = K_NUMBER, FIELD_OF(dome_profile, tilt), CLOSED(0, 90), FLAG_OF(dome_profile, has_tilt)},
    {.key = "size", .type = K_INT, FIELD_OF(dome_profile, size), IRANGE(1, ORR_IMAGE_SIDE_MAX),
     FLAG_OF(dome_profile, has_size)},
};

/* A table of keys, and where its keys are documented (for unknown-key messages). */
typedef struct key_table {
    const key_spec *keys;
    size_t n;
    const char *doc;
} key_table;

#define NKEYS (sizeof KEYS / sizeof KEYS[0])
_Static_assert(NKEYS <= SCENE_MAX_KEYS, "scene_marks has room for every key");
_Static_assert(sizeof PROFILE_KEYS / sizeof PROFILE_KEYS[0] <= SCENE_MAX_KEYS, "and every profile key");

static const key_table SCENE_TABLE = {KEYS, NKEYS, "docs/scenes.md"};
static const key_table PROFILE_TABLE = {PROFILE_KEYS, sizeof PROFILE_KEYS / sizeof PROFILE_KEYS[0],
                                        "domes/README.md"};

/* Longest dotted path the binder builds; longer keys cannot be in the table. */
#define PATH_MAX_LEN 128

static const key_spec *find_key(const key_table *t, const char *path)
{
    for (size_t i = 0; i < t->n; i++)
        if (strcmp(t->keys[i].key, path) == 0)
            return &t->keys[i];
    return NULL;
}

/* A section is a proper prefix of some key, up to a dot ("input.model"). */
static int is_section(const key_table *t, const char *path)
{
    size_t len = strlen(path);
    for (size_t i = 0; i < t->n; i++)
        if (strncmp(t->keys[i].key, path, len) == 0 && t->keys[i].key[len] == '.')
            return 1;
    return 0;
}

const scene_loc *scene_mark(const scene_marks *marks, const char *key)
{
    const key_spec *k = find_key(&SCENE_TABLE, key);
    if (!k)
        return NULL;
    const scene_loc *loc = &marks->loc[k - KEYS];
    return loc->origin ? loc : NULL;
}

void scene_loc_prefix(const char *origin, int line, char *buf, size_t size)
{
    if (line > 0)
        snprintf(buf, size, "%s:%d: ", origin, line);
    else
        snprintf(buf, size, "%s: ", origin);
}

/* ---- messages ---- */

/* The short name keeps the binder's many messages readable. */
#define fail_at scene_fail_at

orr_status scene_fail_at(orr_error *err, const char *origin, int line, const char *fmt, ...)
{
    char prefix[ORR_ERROR_MSG_MAX];
    char text[ORR_ERROR_MSG_MAX];
    scene_loc_prefix(origin, line, prefix, sizeof prefix);
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(text, sizeof text, fmt, ap);
    va_end(ap);
    return orr_fail(err, ORR_ERR_USAGE, "%s%s", prefix, text);
}

/* The value's description for "expected ..., got <what>" messages. */
#define GOT(node) yt_describe((node), got_buf, sizeof got_buf)

/* ---- edit distance, for "did you mean" ---- */

/* Optimal string alignment distance: Levenshtein plus swaps of neighbours,
 * the usual typing mistakes. Strings longer than 63 give a large distance. */
static int edit_distance(const char *a, const char *b)
{
    enum { N = 64 };
    size_t la = strlen(a), lb = strlen(b);
    if (la >= N || lb >= N)
        return INT_MAX;
    int prev2[N], prev[N], cur[N];
    for (size_t j = 0; j <= lb; j++)
        prev[j] = (int)j;
    for (size_t i = 1; i <= la; i++) {
        cur[0] = (int)i;
        for (size_t j = 1; j <= lb; j++) {
            int cost = a[i - 1] != b[j - 1];
            int best = prev[j - 1] + cost;
            if (prev[j] + 1 < best)
                best = prev[j] + 1;
            if (cur[j - 1] + 1 < best)
                best = cur[j - 1] + 1;
            if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1] && prev2[j - 2] + 1 < best)
                best = prev2[j - 2] + 1;
            cur[j] = best;
        }
        memcpy(prev2, prev, sizeof prev);
        memcpy(prev, cur, sizeof cur);
    }
    return prev[lb];
}

static const char *last_part(const char *path)
{
    const char *dot = strrchr(path, '.');
    return dot ? dot + 1 : path;
}

/* The closest key or section to an unknown path: within two edits, or else
 * the only key with the same last part ("camera.height" -> "image.height"). */
static void suggest(const key_table *t, const char *path, char *buf, size_t size)
{
    int best = 3;
    buf[0] = '\0';
    for (size_t i = 0; i < t->n; i++) {
        char cand[PATH_MAX_LEN];
        snprintf(cand, sizeof cand, "%s", t->keys[i].key);
        /* The key itself, then each of its sections, shortest last. */
        for (;;) {
            int d = edit_distance(path, cand);
            if (d < best) {
                best = d;
                snprintf(buf, size, "%s", cand);
            }
            char *dot = strrchr(cand, '.');
            if (!dot)
                break;
            *dot = '\0';
        }
    }
    if (buf[0])
        return;
    const key_spec *only = NULL;
    for (size_t i = 0; i < t->n; i++) {
        if (strcmp(last_part(t->keys[i].key), last_part(path)) == 0) {
            if (only)
                return; /* ambiguous: say nothing */
            only = &t->keys[i];
        }
    }
    if (only)
        snprintf(buf, size, "%s", only->key);
}

/* ---- scalar conversions (no messages; the callers know the key) ---- */

/* "nan", "-inf", ".inf", "Infinity", ...: words people use for non-finite numbers. */
static int is_nonfinite_word(const char *t)
{
    if (*t == '+' || *t == '-')
        t++;
    if (*t == '.')
        t++;
    return strcasecmp(t, "nan") == 0 || strcasecmp(t, "inf") == 0 || strcasecmp(t, "infinity") == 0;
}

/* "nan", ".NaN", "-nan": the words for not-a-number. */
static int is_nan_word(const char *t)
{
    if (*t == '+' || *t == '-')
        t++;
    if (*t == '.')
        t++;
    return strcasecmp(t, "nan") == 0;
}

/* Returns 1 and *v for a finite decimal number, -1 for a number that is not
 * finite (1e999, nan, .inf), 0 for anything else. Only digits, signs, '.' and
 * 'e' are let through to strtod (in the C locale: core/numbers.h), which keeps out its hex, nan and inf forms,
 * and the whole text must be used, which keeps out trailing junk. */
static int parse_number(const char *t, double *v)
{
    if (is_nonfinite_word(t))
        return -1;
    if (t[0] == '\0' || strspn(t, "0123456789+-.eE") != strlen(t) || !strpbrk(t, "0123456789"))
        return 0;
    char *end;
    *v = orr_strtod(t, &end);
    if (*end != '\0')
        return 0;
    return isfinite(*v) ? 1 : -1;
}

/* Integers: plain digits (the full long long range), or a number such as
 * 2e9 or 1.0 whose value is a whole number exactly representable in a double.
 * Returns 1 and *v, 0 when not an integer, -1 when too large. */
static int parse_integer(const char *t, long long *v)
{
    const char *digits = (*t == '+' || *t == '-') ? t + 1 : t;
    if (*digits && strspn(digits, "0123456789") == strlen(digits)) {
        errno = 0;
        *v = strtoll(t, NULL, 10);
        return errno == ERANGE ? -1 : 1;
    }
    double d;
    int ok = parse_number(t, &d);
    if (ok <= 0)
        return ok;
    if (d != floor(d))
        return 0;
    if (fabs(d) > 9007199254740992.0) /* 2^53: beyond it doubles skip integers */
        return -1;
    *v = (long long)d;
    return 1;
}

static int parse_bool(const char *t, int *v)
{
    static const char *const yes[] = {"true", "yes", "on"};
    static const char *const no[] = {"false", "no", "off"};
    for (int i = 0; i < 3; i++) {
        if (strcasecmp(t, yes[i]) == 0) {
            *v = 1;
            return 1;
        }
        if (strcasecmp(t, no[i]) == 0) {
            *v = 0;
            return 1;
        }
    }
    return 0;
}

static int in_bounds(const key_spec *k, double v)
{
    if ((k->bounds & HAS_LO) && ((k->bounds & LO_OPEN) ? !(v > k->lo) : !(v >= k->lo)))
        return 0;
    if ((k->bounds & HAS_HI) && ((k->bounds & HI_OPEN) ? !(v < k->hi) : !(v <= k->hi)))
        return 0;
    return 1;
}

/* "1 to 65536", "must be > 0", "must be > 0 and <= 100". */
static void describe_bounds(const key_spec *k, char *buf, size_t size)
{
    const int lo_closed = (k->bounds & HAS_LO) && !(k->bounds & LO_OPEN);
    const int hi_closed = (k->bounds & HAS_HI) && !(k->bounds & HI_OPEN);
    if (lo_closed && hi_closed) {
        snprintf(buf, size, "%g to %g", k->lo, k->hi);
        return;
    }
    char lo[48] = "", hi[48] = "";
    if (k->bounds & HAS_LO)
        snprintf(lo, sizeof lo, "%s %g", (k->bounds & LO_OPEN) ? ">" : ">=", k->lo);
    if (k->bounds & HAS_HI)
        snprintf(hi, sizeof hi, "%s %g", (k->bounds & HI_OPEN) ? "<" : "<=", k->hi);
    snprintf(buf, size, "must be %s%s%s", lo, (lo[0] && hi[0]) ? " and " : "", hi);
}

/* ---- binding values ---- */

typedef struct bind_ctx {
    void *target;           /* the orr_scene or dome_profile being filled */
    const char *dir;        /* the scene's folder, for K_PATH values */
    const key_table *table;
    scene_marks *marks;
    orr_error *err;
} bind_ctx;

/* Where a value's messages point: the key that holds it, or a list item. */
typedef struct value_at {
    const char *origin;
    int line;
    const char *path; /* "camera.position", "camera.position[1]" */
} value_at;

static void *field(const bind_ctx *c, const key_spec *k) { return (char *)c->target + k->offset; }

/* The scalar text of a value, or an error when it is a list, mapping or null. */
static orr_status want_scalar(const bind_ctx *c, const value_at *at, const yt_node *n, const char *what,
                              const char **text)
{
    char got_buf[96];
    if (n->kind != YT_SCALAR || yt_is_null(n))
        return fail_at(c->err, at->origin, at->line, "%s: expected %s, got %s", at->path, what, GOT(n));
    *text = n->text;
    return ORR_OK;
}

static orr_status get_number(const bind_ctx *c, const key_spec *k, const value_at *at, const yt_node *n,
                             double *v)
{
    const char *t = NULL;
    orr_status st = want_scalar(c, at, n, "a number", &t);
    if (st != ORR_OK)
        return st;
    int ok = parse_number(t, v);
    if (ok <= 0)
        return fail_at(c->err, at->origin, at->line, "%s: expected a %snumber, got '%s'", at->path,
                       ok < 0 ? "finite " : "", t);
    if (k && !in_bounds(k, *v)) {
        char range[128];
        describe_bounds(k, range, sizeof range);
        return fail_at(c->err, at->origin, at->line, "%s: %s is out of range (%s)", at->path, t, range);
    }
    return ORR_OK;
}

static orr_status get_integer(const bind_ctx *c, const value_at *at, const yt_node *n, long long lo,
                              long long hi, long long *v)
{
    const char *t = NULL;
    orr_status st = want_scalar(c, at, n, "an integer", &t);
    if (st != ORR_OK)
        return st;
    int ok = parse_integer(t, v);
    if (is_nan_word(t)) /* not "out of range": NaN is no number at all */
        return fail_at(c->err, at->origin, at->line, "%s: expected an integer, got '%s', which is not a number",
                       at->path, t);
    if (ok == 0)
        return fail_at(c->err, at->origin, at->line, "%s: expected an integer, got '%s'", at->path, t);
    if (ok < 0 || *v < lo || *v > hi)
        return fail_at(c->err, at->origin, at->line, "%s: %s is out of range (%lld to %lld)", at->path, t, lo,
                       hi);
    return ORR_OK;
}

/* What a K_FILENAME key names instead of a path, for its '/' message: the
 * folder of each is set elsewhere. */
static const char *filename_hint(const char *key)
{
    if (strcmp(key, "camera.dome") == 0)
        return "a dome profile's name, e.g. flat-180, found in the domes folders; see docs/scenes.md#dome-profiles";
    if (strcmp(key, "output.image") == 0)
        return "a file extension such as tif or jpg; the folder is output.dir";
    return "the folder is output.dir";
}

static orr_status bind_text(const bind_ctx *c, const key_spec *k, const value_at *at, const yt_node *n)
{
    const char *t = NULL;
    orr_status st = want_scalar(c, at, n, k->type == K_PATH ? "a file path" : "a string", &t);
    if (st != ORR_OK)
        return st;
    if (t[0] == '\0')
        return fail_at(c->err, at->origin, at->line, "%s: must not be empty", at->path);
    if (k->type == K_FILENAME && strchr(t, '/'))
        return fail_at(c->err, at->origin, at->line, "%s: '%s' must be a file name, without '/' (%s)", at->path, t,
                       filename_hint(k->key));
    /* Paths in the scene are relative to its folder, so a scene and its data
     * can move together; a --set path (line 0) was typed in a shell, so it
     * stays relative to the working directory like any other argument. "-"
     * (standard input) is no path. */
    const int from_scene = at->line > 0;
    int len;
    if (k->type == K_PATH && from_scene && t[0] != '/' && strcmp(c->dir, ".") != 0 && strcmp(t, "-") != 0)
        len = snprintf(field(c, k), k->size, "%s/%s", c->dir, t);
    else
        len = snprintf(field(c, k), k->size, "%s", t);
    if (len < 0 || (size_t)len >= k->size)
        return fail_at(c->err, at->origin, at->line, "%s: '%.60s...' is too long (at most %zu characters)",
                       at->path, t, k->size - 1);
    return ORR_OK;
}

static orr_status bind_enum(const bind_ctx *c, const key_spec *k, const value_at *at, const yt_node *n)
{
    char what[160], note[160] = "", got_buf[96];
    snprintf(what, sizeof what, "one of: %s", k->choices());
    if (k->choices_note)
        snprintf(note, sizeof note, " (%s)", k->choices_note);
    /* Only the scene table has words, so the target is an orr_scene. */
    if (n->kind == YT_SCALAR && !yt_is_null(n) && k->parse_word((orr_scene *)c->target, n->text))
        return ORR_OK;
    return fail_at(c->err, at->origin, at->line, "%s: expected %s, got %s%s", at->path, what, GOT(n), note);
}

static orr_status bind_named(const bind_ctx *c, const key_spec *k, const value_at *at, const yt_node *n)
{
    int v;
    if (k->size != sizeof v)
        return orr_fail(c->err, ORR_ERR_INTERNAL, "%s: the key's field is not int-sized", at->path);
    if (n->kind == YT_SCALAR && !yt_is_null(n) && orr_named_value(k->names, n->text, &v)) {
        memcpy(field(c, k), &v, sizeof v);
        return ORR_OK;
    }
    char words[160], got_buf[96];
    return fail_at(c->err, at->origin, at->line, "%s: expected one of: %s, got %s", at->path,
                   orr_named_list(k->names, words, sizeof words), GOT(n));
}

static orr_status bind_bool(const bind_ctx *c, const key_spec *k, const value_at *at, const yt_node *n)
{
    const char *t = NULL;
    orr_status st = want_scalar(c, at, n, "true or false", &t);
    if (st != ORR_OK)
        return st;
    int v;
    if (!parse_bool(t, &v))
        return fail_at(c->err, at->origin, at->line, "%s: expected true or false, got '%s'", at->path, t);
    memcpy(field(c, k), &v, sizeof v);
    return ORR_OK;
}

/* Particle ids: plain digits up to 2^64 - 1 (ids near the top of the range
 * are real: some codes hash them), or any integer form get_integer takes. */
static orr_status bind_id(const bind_ctx *c, const key_spec *k, const value_at *at, const yt_node *n)
{
    const char *t = NULL;
    orr_status st = want_scalar(c, at, n, "a particle id (an integer >= 0)", &t);
    if (st != ORR_OK)
        return st;
    const char *digits = t[0] == '+' ? t + 1 : t;
    uint64_t id;
    if (digits[0] && strspn(digits, "0123456789") == strlen(digits)) {
        errno = 0;
        unsigned long long v = strtoull(digits, NULL, 10);
        if (errno == ERANGE) /* unsigned long long is 64 bits wide on every platform we build on */
            return fail_at(c->err, at->origin, at->line, "%s: %s is out of range (0 to %llu)", at->path, t,
                           (unsigned long long)UINT64_MAX);
        id = (uint64_t)v;
    } else {
        long long v;
        if ((st = get_integer(c, at, n, 0, LLONG_MAX, &v)) != ORR_OK)
            return st;
        id = (uint64_t)v;
    }
    memcpy(field(c, k), &id, sizeof id);
    return ORR_OK;
}

static orr_status bind_integer(const bind_ctx *c, const key_spec *k, const value_at *at, const yt_node *n)
{
    long long v;
    orr_status st = get_integer(c, at, n, k->ilo, k->ihi, &v);
    if (st != ORR_OK)
        return st;
    if (k->type == K_INT) {
        int i = (int)v; /* the range check above keeps it within int */
        memcpy(field(c, k), &i, sizeof i);
    } else if (k->type == K_U64) {
        uint64_t u = (uint64_t)v; /* ilo >= 0 */
        memcpy(field(c, k), &u, sizeof u);
    } else {
        memcpy(field(c, k), &v, sizeof v);
    }
    return ORR_OK;
}

static orr_status bind_number(const bind_ctx *c, const key_spec *k, const value_at *at, const yt_node *n)
{
    double v = 0; /* "auto": the stretch takes its white from a percentile */
    const int is_auto = n->kind == YT_SCALAR && strcmp(n->text, "auto") == 0;
    if (k->type == K_AUTO && !is_auto && (n->kind != YT_SCALAR || parse_number(n->text, &v) == 0)) {
        char got_buf[96];
        return fail_at(c->err, at->origin, at->line, "%s: expected a number or auto, got %s", at->path, GOT(n));
    }
    if (k->type != K_AUTO || !is_auto) {
        orr_status st = get_number(c, k, at, n, &v);
        if (st != ORR_OK)
            return st;
    }
    memcpy(field(c, k), &v, sizeof v);
    return ORR_OK;
}

/* A number, or the word run: the value then follows the frame's place in
 * the run (0 at the first frame, 1 at the last), which the renderer reads
 * from the int the table's RUN_FLAG names: 1 for run, 0 for a number, so
 * that a --set number overrides a file's run and the other way round. */
static orr_status bind_run(const bind_ctx *c, const key_spec *k, const value_at *at, const yt_node *n)
{
    const int is_run = n->kind == YT_SCALAR && strcmp(n->text, "run") == 0;
    double v = 0;
    if (!is_run) {
        double probe;
        if (n->kind != YT_SCALAR || parse_number(n->text, &probe) == 0) {
            char got_buf[96];
            return fail_at(c->err, at->origin, at->line, "%s: expected a number or run, got %s", at->path,
                           GOT(n));
        }
        orr_status st = get_number(c, k, at, n, &v);
        if (st != ORR_OK)
            return st;
    }
    memcpy(field(c, k), &v, sizeof v);
    memcpy((char *)c->target + k->flag_offset, &is_run, sizeof is_run);
    return ORR_OK;
}

/* The n numbers of a list value ([x, y, z] or [w, x, y, z]). */
static orr_status get_numbers(const bind_ctx *c, const value_at *at, const yt_node *n, size_t count,
                              const char *form, double *out)
{
    char got_buf[96];
    if (n->kind != YT_SEQUENCE)
        return fail_at(c->err, at->origin, at->line, "%s: expected a list of %zu numbers %s, got %s", at->path,
                       count, form, GOT(n));
    if (n->n != count)
        return fail_at(c->err, at->origin, at->line, "%s: expected a list of %zu numbers %s, got a list of %zu",
                       at->path, count, form, n->n);
    for (size_t i = 0; i < count; i++) {
        char path[PATH_MAX_LEN + 16];
        snprintf(path, sizeof path, "%s[%zu]", at->path, i);
        const yt_node *item = n->items[i];
        value_at item_at = {item->origin, item->line ? item->line : at->line, path};
        orr_status st = get_number(c, NULL, &item_at, item, &out[i]);
        if (st != ORR_OK)
            return st;
    }
    return ORR_OK;
}

static orr_status bind_vector(const bind_ctx *c, const key_spec *k, const value_at *at, const yt_node *n)
{
    double v[4];
    if (k->type == K_VEC3) {
        orr_status st = get_numbers(c, at, n, 3, "[x, y, z]", v);
        if (st != ORR_OK)
            return st;
        orr_vec3 vec = {v[0], v[1], v[2]};
        memcpy(field(c, k), &vec, sizeof vec);
    } else {
        orr_status st = get_numbers(c, at, n, 4, "[w, x, y, z]", v);
        if (st != ORR_OK)
            return st;
        orr_quat q = {v[0], v[1], v[2], v[3]};
        memcpy(field(c, k), &q, sizeof q);
    }
    return ORR_OK;
}

/* [l, b] in degrees: l wraps around, so any finite value is fine; b is a latitude. */
static orr_status bind_lb(const bind_ctx *c, const key_spec *k, const value_at *at, const yt_node *n)
{
    double lb[2];
    orr_status st = get_numbers(c, at, n, 2, "[l, b] in degrees", lb);
    if (st != ORR_OK)
        return st;
    if (!(lb[1] >= -90 && lb[1] <= 90)) {
        const yt_node *b = n->items[1];
        return fail_at(c->err, b->origin, b->line ? b->line : at->line,
                       "%s[1]: %s is out of range (-90 to 90: b is a latitude)", at->path, b->text);
    }
    memcpy(field(c, k), lb, sizeof lb);
    return ORR_OK;
}

static orr_status bind_pair(const bind_ctx *c, const key_spec *k, const value_at *at, const yt_node *n)
{
    double ab[2];
    orr_status st = get_numbers(c, at, n, 2, "[first, last]", ab);
    if (st == ORR_OK)
        memcpy(field(c, k), ab, sizeof ab);
    return st;
}

/* input.types: a list of types 0..5 (or one type alone) to a bit mask. */
static orr_status bind_types(const bind_ctx *c, const key_spec *k, const value_at *at, const yt_node *n)
{
    char got_buf[96];
    const yt_node *const *items = &n;
    size_t count = 1;
    if (n->kind == YT_SEQUENCE) {
        items = (const yt_node *const *)n->items;
        count = n->n;
    } else if (n->kind != YT_SCALAR || yt_is_null(n)) {
        return fail_at(c->err, at->origin, at->line, "%s: expected a list of particle types 0 to 5, got %s",
                       at->path, GOT(n));
    }
    if (count == 0)
        return fail_at(c->err, at->origin, at->line, "%s: the list is empty; give at least one particle type",
                       at->path);
    unsigned mask = 0;
    for (size_t i = 0; i < count; i++) {
        char path[PATH_MAX_LEN + 16];
        if (n->kind == YT_SEQUENCE)
            snprintf(path, sizeof path, "%s[%zu]", at->path, i);
        else
            snprintf(path, sizeof path, "%s", at->path);
        value_at item_at = {items[i]->origin, items[i]->line ? items[i]->line : at->line, path};
        long long t;
        orr_status st = get_integer(c, &item_at, items[i], 0, 5, &t);
        if (st != ORR_OK)
            return st;
        mask |= 1u << t;
    }
    memcpy(field(c, k), &mask, sizeof mask);
    return ORR_OK;
}

static orr_status bind_value(const bind_ctx *c, const key_spec *k, const value_at *at, const yt_node *n)
{
    switch (k->type) {
    case K_STRING:
    case K_FILENAME:
    case K_PATH: return bind_text(c, k, at, n);
    case K_NUMBER:
    case K_AUTO: return bind_number(c, k, at, n);
    case K_RUN: return bind_run(c, k, at, n);
    case K_INT:
    case K_LLONG:
    case K_U64: return bind_integer(c, k, at, n);
    case K_BOOL: return bind_bool(c, k, at, n);
    case K_ENUM: return bind_enum(c, k, at, n);
    case K_NAMED: return bind_named(c, k, at, n);
    case K_VEC3:
    case K_QUAT: return bind_vector(c, k, at, n);
    case K_TYPES: return bind_types(c, k, at, n);
    case K_POPULATIONS: return scene_bind_populations(c->target, at->origin, at->line, at->path, n, c->err);
    case K_TINT: return scene_bind_tint(c->target, at->origin, at->line, at->path, n, c->err);
    case K_LAYERS: return scene_bind_layers(c->target, at->origin, at->line, at->path, n, c->err);
    case K_SEQ_FILES: return scene_bind_sequence_files(c->target, at->origin, at->line, at->path, n, c->err);
    case K_ID: return bind_id(c, k, at, n);
    case K_LB: return bind_lb(c, k, at, n);
    case K_PAIR: return bind_pair(c, k, at, n);
    case K_KEYFRAMES: return scene_bind_keyframes(c->target, at->origin, at->line, at->path, n, c->err);
    }
    return orr_fail(c->err, ORR_ERR_INTERNAL, "%s: unknown key type %d", k->key, (int)k->type);
}

/* ---- walking the tree ---- */

static orr_status bind_mapping(const bind_ctx *c, const yt_node *map, const char *prefix);

/* Checks a key on its own: not empty, no dots (nesting is written as
 * mappings, so "camera.fov:" in a file would silently bypass the duplicate
 * check), and not already used in the same mapping. */
static orr_status check_key(const bind_ctx *c, const yt_node *map, size_t i, const char *prefix)
{
    const yt_entry *e = &map->entries[i];
    const char *sep = prefix[0] ? "." : "";
    if (e->key[0] == '\0')
        return fail_at(c->err, e->origin, e->line, "empty key%s%s", prefix[0] ? " in " : "", prefix);
    if (strchr(e->key, '.'))
        return fail_at(c->err, e->origin, e->line,
                       "key '%s%s%s' contains a '.'; write nested keys as indented mappings", prefix, sep, e->key);
    for (size_t j = 0; j < i; j++) {
        const yt_entry *first = &map->entries[j];
        if (strcmp(first->key, e->key) == 0)
            return fail_at(c->err, e->origin, e->line, "duplicate key '%s%s%s' (first set at line %d)", prefix,
                           sep, e->key, first->line);
    }
    return ORR_OK;
}

static orr_status unknown_key(const bind_ctx *c, const yt_entry *e, const char *path)
{
    char hint[PATH_MAX_LEN];
    suggest(c->table, path, hint, sizeof hint);
    if (hint[0])
        return fail_at(c->err, e->origin, e->line, "unknown key '%s' (did you mean '%s'?)", path, hint);
    return fail_at(c->err, e->origin, e->line, "unknown key '%s' (see %s for the keys)", path, c->table->doc);
}

static orr_status bind_entry(const bind_ctx *c, const yt_entry *e, const char *path)
{
    const key_spec *k = find_key(c->table, path);
    if (k) {
        value_at at = {e->origin, e->line, path};
        orr_status st = bind_value(c, k, &at, e->value);
        if (st != ORR_OK)
            return st;
        c->marks->loc[k - c->table->keys] = (scene_loc){e->origin, e->line};
        if (k->has_flag) {
            int one = 1;
            memcpy((char *)c->target + k->flag_offset, &one, sizeof one);
        }
        return ORR_OK;
    }
    if (!is_section(c->table, path))
        return unknown_key(c, e, path);
    if (e->value->kind == YT_MAPPING)
        return bind_mapping(c, e->value, path);
    if (yt_is_null(e->value))
        return ORR_OK; /* "camera:" with every key commented out */
    char got_buf[96];
    return fail_at(c->err, e->origin, e->line, "%s: expected a mapping of %s.* keys, got %s", path, path,
                   GOT(e->value));
}

static orr_status bind_mapping(const bind_ctx *c, const yt_node *map, const char *prefix)
{
    for (size_t i = 0; i < map->n; i++) {
        const yt_entry *e = &map->entries[i];
        orr_status st = check_key(c, map, i, prefix);
        if (st != ORR_OK)
            return st;
        char path[PATH_MAX_LEN];
        int len = snprintf(path, sizeof path, "%s%s%s", prefix, prefix[0] ? "." : "", e->key);
        if (len < 0 || (size_t)len >= sizeof path)
            return fail_at(c->err, e->origin, e->line, "unknown key '%.60s...' (too long)", path);
        st = bind_entry(c, e, path);
        if (st != ORR_OK)
            return st;
    }
    return ORR_OK;
}

orr_status scene_bind(orr_scene *s, const yt_node *root, scene_marks *marks, orr_error *err)
{
    memset(marks, 0, sizeof *marks);
    bind_ctx c = {s, s->dir, &SCENE_TABLE, marks, err};
    return bind_mapping(&c, root, "");
}

orr_status dome_profile_bind(dome_profile *p, const yt_node *root, orr_error *err)
{
    scene_marks marks; /* a profile's keys have no checks across them */
    bind_ctx c = {p, ".", &PROFILE_TABLE, &marks, err};
    memset(&marks, 0, sizeof marks);
    return bind_mapping(&c, root, "");
}

orr_status scene_fail_key(const orr_scene *s, const scene_marks *m, const char *key, orr_error *err,
                          const char *fmt, ...)
{
    char prefix[ORR_PATH_MAX + 32]; /* room for s->path; orr_fail cuts the message to size */
    char text[ORR_ERROR_MSG_MAX];
    const scene_loc *loc = scene_mark(m, key);
    scene_loc_prefix(loc ? loc->origin : s->path, loc ? loc->line : 0, prefix, sizeof prefix);
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(text, sizeof text, fmt, ap);
    va_end(ap);
    return orr_fail(err, ORR_ERR_USAGE, "%s%s", prefix, text);
}
