#include "scene/scene_keys.h"

#include <limits.h>
#include <stddef.h>
#include <stdio.h>
#include <string.h>

#include "encode/fits.h"
#include "scene/scene_bind.h"
#include "source/models/model.h"
#include "source/source.h"

/* ---- the table of keys ---- */

#define FIELD_OF(type, m) .offset = offsetof(type, m), .size = sizeof(((type *)0)->m)
#define FLAG_OF(type, m) .has_flag = 1, .flag_offset = offsetof(type, m)
#define FIELD(m) FIELD_OF(orr_scene, m)
/* A file or folder name: an owned string of at most ORR_PATH_MAX - 1 characters. */
#define OWNED_PATH(m) .offset = offsetof(orr_scene, m), .size = ORR_PATH_MAX, .owned = 1
#define FLAG(m) FLAG_OF(orr_scene, m)
/* K_RUN: the int field set to 1 for the word run, 0 for a number. */
#define RUN_FLAG(m) .flag_offset = offsetof(orr_scene, m)
#define IRANGE(a, b) .ilo = (a), .ihi = (b)
#define ABOVE(a) .lo = (a), .bounds = HAS_LO | LO_OPEN
#define CLOSED(a, b) .lo = (a), .hi = (b), .bounds = HAS_LO | HAS_HI

/* Word parsers for the keys whose words are names rather than an enumeration:
 * the file formats the readers register, and the built-in models. */
static int word_input_format(orr_scene *s, const char *w)
{
    if (strcmp(w, "auto") != 0 && !orr_source_format_known(w))
        return 0;
    snprintf(s->input.format, sizeof s->input.format, "%s", w);
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
    snprintf(s->input.model.name, sizeof s->input.model.name, "%s", w);
    return 1;
}
static const char *names_model_name(void) { return "mw-m31 king"; }

#define ENUM(fn) .type = K_ENUM, .parse_word = word_##fn, .choices = names_##fn
/* The field must be int-sized: the table's value is stored as an int. */
#define NAMED(table, m) .type = K_NAMED, .names = (table), FIELD(m)
/* camera.projection lists the flat projections after "one of:" and the sky
 * maps in a note after the value, which keeps the message of a mistyped
 * flat one short. */
#define SKY_MAPS_NOTED .names_shown = 2, .names_note = "sky maps"

static const key_spec KEYS[] = {
    {.key = "input.file", .type = K_PATH, OWNED_PATH(input.file)},
    {.key = "input.format", ENUM(input_format)},
    {.key = "input.model.name", ENUM(model_name)},
    {.key = "input.model.particles", .type = K_LLONG, FIELD(input.model.particles), IRANGE(100, 2000000000LL)},
    {.key = "input.model.seed", .type = K_U64, FIELD(input.model.seed), IRANGE(0, LLONG_MAX)},
    {.key = "input.model.separation", .type = K_NUMBER, FIELD(input.model.separation), ABOVE(0)},
    {.key = "input.model.galaxies", NAMED(orr_model_galaxies_names, input.model.galaxies)},
    {.key = "input.model.disc_q", .type = K_NUMBER, FIELD(input.model.disc_q), ABOVE(0)},
    {.key = "input.model.m31_weight", .type = K_NUMBER, FIELD(input.model.m31_weight),
     CLOSED(1.0 / ORR_MODEL_M31_WEIGHT_MAX, ORR_MODEL_M31_WEIGHT_MAX)},
    {.key = "input.model.w0", .type = K_NUMBER, FIELD(input.model.w0), CLOSED(0.5, 15)},
    {.key = "input.model.core_radius", .type = K_NUMBER, FIELD(input.model.core_radius), ABOVE(0)},
    {.key = "input.model.mass", .type = K_NUMBER, FIELD(input.model.mass), ABOVE(0)},
    {.key = "input.model.dust_particles", .type = K_LLONG, FIELD(input.model.dust_particles), IRANGE(0, 2000000000LL)},
    {.key = "input.model.dust_clumping", .type = K_NUMBER, FIELD(input.model.dust_clumping), CLOSED(0, 3)},
    {.key = "input.weight", .type = K_STRING, FIELD(input.weight)},
    {.key = "input.types", .type = K_TYPES, FIELD(input.type_mask)},
    {.key = "input.chunk", .type = K_LLONG, FIELD(input.chunk_size), IRANGE(1, 4294967296LL)},
    {.key = "input.nonfinite", NAMED(orr_nonfinite_names, input.skip_nonfinite)},
    {.key = "input.periodic.box", .type = K_AUTO, FIELD(periodic.box), ABOVE(0)},
    {.key = "input.periodic.replicas", .type = K_INT, FIELD(periodic.replicas), IRANGE(1, 9)},
    {.key = "input.periodic.centre", NAMED(orr_periodic_centre_names, periodic.around_camera)},
    {.key = "input.periodic.radius", .type = K_AUTO, FIELD(periodic.radius), ABOVE(0)},
    {.key = "input.periodic.fade", .type = K_NUMBER, FIELD(periodic.fade), .lo = 0, .bounds = HAS_LO,
     FLAG(periodic.has_fade)},
    {.key = "input.insitu", .type = K_BOOL, FIELD(input.insitu)},
    {.key = "input.sequence.pattern", .type = K_PATH, OWNED_PATH(input.sequence.pattern)},
    {.key = "input.sequence.first", .type = K_LLONG, FIELD(input.sequence.first), IRANGE(0, 1000000000LL)},
    {.key = "input.sequence.last", .type = K_LLONG, FIELD(input.sequence.last), IRANGE(0, 1000000000LL)},
    {.key = "input.sequence.step", .type = K_LLONG, FIELD(input.sequence.step), IRANGE(1, 1000000000LL)},
    {.key = "input.sequence.files", .type = K_SEQ_FILES},
    {.key = "input.sequence.interpolation", NAMED(orr_interpolation_names, input.sequence.interpolation)},
    {.key = "input.sequence.max_memory", .type = K_NUMBER, FIELD(input.sequence.max_memory), ABOVE(0)},
    {.key = "camera.position", .type = K_VEC3, FIELD(camera.position)},
    {.key = "camera.look_at", .type = K_VEC3, FIELD(camera.look_at), FLAG(camera.has_look_at)},
    {.key = "camera.direction", .type = K_VEC3, FIELD(camera.direction), FLAG(camera.has_direction)},
    {.key = "camera.up", .type = K_VEC3, FIELD(camera.up), FLAG(camera.has_up)},
    {.key = "camera.roll", .type = K_NUMBER, FIELD(camera.roll)},
    {.key = "camera.quaternion", .type = K_QUAT, FIELD(camera.quaternion), FLAG(camera.has_quaternion)},
    {.key = "camera.path.kind", NAMED(orr_path_kind_names, camera.path.kind), FLAG(camera.has_path)},
    {.key = "camera.path.keyframes", .type = K_KEYFRAMES},
    {.key = "camera.path.file", .type = K_PATH, OWNED_PATH(camera.path_file)},
    {.key = "camera.path.interpolation", NAMED(orr_path_interp_names, camera.path.interpolation)},
    {.key = "camera.path.orientation", NAMED(orr_path_orient_names, camera.path.orientation)},
    {.key = "camera.path.ease", NAMED(orr_ease_names, camera.path.ease)},
    {.key = "camera.path.centre", .type = K_VEC3, FIELD(camera.path.centre)},
    {.key = "camera.path.target", .type = K_VEC3, FIELD(camera.path.centre)},
    {.key = "camera.path.axis", .type = K_VEC3, FIELD(camera.path.axis)},
    {.key = "camera.path.radius", .type = K_NUMBER, FIELD(camera.path.radius), ABOVE(0)},
    {.key = "camera.path.start", .type = K_VEC3, FIELD(camera.path_start), FLAG(camera.has_path_start)},
    {.key = "camera.path.start_angle", .type = K_NUMBER, FIELD(camera.path.start_angle)},
    {.key = "camera.path.turns", .type = K_NUMBER, FIELD(camera.path.turns)},
    {.key = "camera.path.r0", .type = K_NUMBER, FIELD(camera.path.r0), ABOVE(0)},
    {.key = "camera.path.r1", .type = K_NUMBER, FIELD(camera.path.r1), ABOVE(0)},
    {.key = "camera.path.radial", NAMED(orr_radial_law_names, camera.path.radial)},
    {.key = "camera.path.from", .type = K_VEC3, FIELD(camera.path.from)},
    {.key = "camera.path.to", .type = K_VEC3, FIELD(camera.path.to)},
    {.key = "camera.path.look_at", .type = K_VEC3, FIELD(camera.path.look_at), FLAG(camera.path.has_look_at)},
    {.key = "camera.path.up", .type = K_VEC3, FIELD(camera.path.up)},
    {.key = "camera.path.angle", .type = K_NUMBER, FIELD(camera.path.angle)},
    {.key = "camera.projection", NAMED(orr_projection_names, projection.kind), SKY_MAPS_NOTED},
    {.key = "camera.width", .type = K_NUMBER, FIELD(projection.ortho_width)},
    {.key = "camera.fov", .type = K_NUMBER, FIELD(projection.fov_deg)},
    {.key = "camera.near", .type = K_NUMBER, FIELD(projection.near)},
    {.key = "camera.lon_flip", .type = K_BOOL, FIELD(projection.lon_flip)},
    {.key = "camera.healpix_nside", .type = K_INT, FIELD(projection.healpix_nside), IRANGE(1, ORR_HEALPIX_NSIDE_MAX)},
    {.key = "camera.healpix_order", NAMED(orr_healpix_order_names, projection.healpix_nested)},
    {.key = "camera.dome", .type = K_FILENAME, FIELD(camera.dome)},
    {.key = "camera.dome_fov", .type = K_NUMBER, FIELD(projection.dome_fov_deg)},
    {.key = "camera.dome_tilt", .type = K_NUMBER, FIELD(camera.dome_tilt), CLOSED(0, 90)},
    {.key = "camera.zenith", .type = K_LB, FIELD(camera.zenith_lb), FLAG(camera.has_zenith)},
    {.key = "camera.front", .type = K_LB, FIELD(camera.front_lb), FLAG(camera.has_front)},
    {.key = "image.width", .type = K_INT, FIELD(projection.width), IRANGE(1, ORR_IMAGE_SIDE_MAX)},
    {.key = "image.height", .type = K_INT, FIELD(projection.height), IRANGE(1, ORR_IMAGE_SIDE_MAX)},
    {.key = "deposit", NAMED(orr_deposit_names, deposit.kind)},
    {.key = "smoothing.kernel", NAMED(orr_kernel_names, deposit.kernel)},
    {.key = "smoothing.lengths", NAMED(orr_smoothing_source_names, deposit.lengths)},
    {.key = "smoothing.neighbours", .type = K_INT, FIELD(deposit.neighbours), IRANGE(1, 4096)},
    {.key = "smoothing.h_scale", .type = K_NUMBER, FIELD(deposit.h_scale), ABOVE(0)},
    {.key = "colour.populations", .type = K_POPULATIONS},
    {.key = "colour.only", .type = K_STRING, FIELD(colour.only)},
    {.key = "colour.seed", .type = K_U64, FIELD(colour.seed), IRANGE(0, LLONG_MAX)},
    {.key = "colour.synthesis.stretch", NAMED(orr_lum_stretch_names, colour.synth.stretch)},
    {.key = "colour.synthesis.softening", .type = K_NUMBER, FIELD(colour.synth.n), ABOVE(0)},
    {.key = "colour.synthesis.gamma", .type = K_NUMBER, FIELD(colour.synth.gamma), ABOVE(0)},
    {.key = "colour.synthesis.white", .type = K_AUTO, FIELD(colour.synth.y0), ABOVE(0)},
    {.key = "colour.synthesis.white_percentile", .type = K_NUMBER, FIELD(colour.synth.y0_percentile), .lo = 0, .hi = 100,
     .bounds = HAS_LO | LO_OPEN | HAS_HI},
    {.key = "colour.synthesis.brightness", .type = K_NUMBER, FIELD(colour.synth.brightness), ABOVE(0)},
    {.key = "colour.synthesis.contrast", .type = K_NUMBER, FIELD(colour.synth.contrast), ABOVE(0)},
    {.key = "colour.synthesis.clip", NAMED(orr_clip_names, colour.synth.clip)},
    {.key = "colour.tint.path", .type = K_TINT},
    {.key = "compose.layers", .type = K_LAYERS},
    {.key = "colour.tint.t", .type = K_RUN, FIELD(colour.tint_t), CLOSED(0, 1), RUN_FLAG(colour.tint_run)},
    {.key = "psf.kind", NAMED(orr_psf_kind_names, psf.kind)},
    {.key = "psf.fwhm", .type = K_NUMBER, FIELD(psf.fwhm), CLOSED(0.1, 1000), FLAG(psf.has_fwhm)},
    {.key = "psf.fwhm_arcmin", .type = K_AUTO, FIELD(psf.fwhm_arcmin), CLOSED(0.01, 3000)},
    {.key = "psf.file", .type = K_PATH, OWNED_PATH(psf.file)},
    {.key = "psf.file_subsample", .type = K_INT, FIELD(psf.file_subsample), IRANGE(1, 64)},
    {.key = "psf.arcsec_per_pixel", .type = K_NUMBER, FIELD(psf.arcsec_per_pixel), .lo = 0, .bounds = HAS_LO},
    {.key = "psf.angle", .type = K_NUMBER, FIELD(psf.angle)},
    {.key = "psf.vane_width", .type = K_NUMBER, FIELD(psf.vane_width), CLOSED(0.001, 0.2)},
    {.key = "psf.spike_gain", .type = K_NUMBER, FIELD(psf.spike_gain), CLOSED(1, 1000)},
    {.key = "psf.size", .type = K_INT, FIELD(psf.size), IRANGE(3, 2047)},
    {.key = "psf.spike_stars", .type = K_INT, FIELD(psf.spike_stars), IRANGE(0, 100000)},
    {.key = "psf.spike_min_flux", .type = K_NUMBER, FIELD(psf.spike_min_flux), CLOSED(0, 1)},
    {.key = "psf.spike_flux", .type = K_NUMBER, FIELD(psf.spike_flux), .lo = 0, .bounds = HAS_LO},
    {.key = "glow.threshold", .type = K_NUMBER, FIELD(psf.glow_threshold), .lo = 0, .bounds = HAS_LO,
     FLAG(psf.has_glow)},
    {.key = "glow.max_arcmin", .type = K_NUMBER, FIELD(psf.glow_max_arcmin), ABOVE(0)},
    {.key = "observer.id", .type = K_ID, FIELD(observer.id), FLAG(observer.has_id)},
    {.key = "observer.reference_id", .type = K_ID, FIELD(observer.reference_id)},
    {.key = "observer.normal", .type = K_VEC3, FIELD(observer.normal), FLAG(observer.has_normal)},
    {.key = "observer.normal_from.types", .type = K_TYPES, FIELD(observer.normal_types)},
    {.key = "observer.normal_from.radius", .type = K_NUMBER, FIELD(observer.normal_radius), ABOVE(0)},
    {.key = "observer.normal_from.sign", NAMED(orr_normal_sign_names, observer.normal_sign)},
    {.key = "observer.dim", .type = K_BOOL, FIELD(observer.dim)},
    {.key = "observer.dim_near", .type = K_NUMBER, FIELD(observer.dim_near), ABOVE(0)},
    {.key = "camera.dim", .type = K_BOOL, FIELD(camera.dim)},
    {.key = "camera.dim_near", .type = K_NUMBER, FIELD(camera.dim_near), ABOVE(0)},
    {.key = "stars.limit", .type = K_NUMBER, FIELD(stars.limit), CLOSED(-30, 30), FLAG(stars.enabled)},
    {.key = "stars.types", .type = K_TYPES, FIELD(stars.types)},
    {.key = "stars.light_unit", .type = K_NUMBER, FIELD(stars.light_unit), ABOVE(0)},
    {.key = "stars.mass_unit", .type = K_NUMBER, FIELD(stars.mass_unit), ABOVE(0)},
    {.key = "stars.length_unit", .type = K_NUMBER, FIELD(stars.length_unit), ABOVE(0)},
    {.key = "stars.spread", .type = K_NUMBER, FIELD(stars.spread), .lo = 0, .bounds = HAS_LO},
    {.key = "stars.glow_max", .type = K_NUMBER, FIELD(stars.glow_max_deg), .lo = 0, .hi = 90, .bounds = HAS_LO | LO_OPEN | HAS_HI},
    {.key = "stars.seed", .type = K_U64, FIELD(stars.seed), IRANGE(0, LLONG_MAX)},
    {.key = "stars.max", .type = K_LLONG, FIELD(stars.max_stars), IRANGE(1, 100000000)},
    {.key = "stars.list", .type = K_BOOL, FIELD(stars.list)},
    {.key = "dust.types", .type = K_TYPES, FIELD(dust.types)},
    {.key = "dust.kappa_v", .type = K_NUMBER, FIELD(dust.kappa_v), ABOVE(0)},
    {.key = "dust.dust_to_gas", .type = K_NUMBER, FIELD(dust.dust_to_gas), ABOVE(0)},
    {.key = "dust.metallicity", .type = K_STRING, FIELD(dust.metallicity)},
    {.key = "dust.z_sun", .type = K_NUMBER, FIELD(dust.z_sun), ABOVE(0)},
    {.key = "dust.curve", NAMED(orr_dust_curve_names, dust.curve)},
    {.key = "dust.r_v", .type = K_NUMBER, FIELD(dust.r_v), CLOSED(1, 10)},
    {.key = "dust.curve_file", .type = K_PATH, OWNED_PATH(dust.curve_file)},
    {.key = "dust.extinction_plane", .type = K_BOOL, FIELD(dust.extinction_plane)},
    {.key = "animation.frames", .type = K_LLONG, FIELD(animation.frames), IRANGE(1, 10000000)},
    {.key = "animation.fps", .type = K_NUMBER, FIELD(animation.fps), CLOSED(0.001, 1000)},
    {.key = "animation.white_smoothing", .type = K_INT, FIELD(animation.white_smoothing), IRANGE(0, 100000)},
    {.key = "animation.time", .type = K_PAIR, FIELD(animation.time), FLAG(animation.has_time)},
    {.key = "animation.shutter", .type = K_NUMBER, FIELD(animation.shutter), CLOSED(0, 1)},
    {.key = "animation.frame_interval", .type = K_NUMBER, FIELD(animation.frame_interval), .lo = 0, .bounds = HAS_LO,
     FLAG(animation.has_frame_interval)},

    {.key = "stereo.mode", NAMED(orr_stereo_mode_names, stereo.mode)},
    {.key = "stereo.eye_separation", .type = K_NUMBER, FIELD(stereo.eye_separation), ABOVE(0)},
    {.key = "stereo.convergence", .type = K_AUTO, FIELD(stereo.convergence), ABOVE(0)},
    {.key = "stereo.anaglyph", NAMED(orr_anaglyph_names, picture.anaglyph)},
    {.key = "stereo.zenith_fade", .type = K_NUMBER, FIELD(stereo.zenith_fade), CLOSED(0, 90)},
    {.key = "output.dir", .type = K_STRING, OWNED_PATH(output.dir)},
    {.key = "output.name", .type = K_FILENAME, FIELD(output.name)},
    {.key = "output.fits", .type = K_BOOL, FIELD(output.write_fits)},
    {.key = "output.png", .type = K_BOOL, FIELD(output.write_png)},
    {.key = "output.raw", .type = K_BOOL, FIELD(output.write_raw)},
    {.key = "output.png_transfer", NAMED(orr_png_transfer_names, output.png_linear)},
    {.key = "output.exr", .type = K_BOOL, FIELD(output.write_exr)},
    {.key = "output.exr_half", .type = K_BOOL, FIELD(output.exr_half)},
    {.key = "output.exr_population_layers", .type = K_BOOL, FIELD(output.exr_population_layers)},
    {.key = "output.fits_compress", NAMED(orr_fits_compression_names, output.fits_compress)},
    {.key = "output.image", .type = K_FILENAME, FIELD(output.image_ext)},
    {.key = "output.png_bits", NAMED(orr_png_bits_names, output.png_bits)},
    {.key = "output.stretch", NAMED(orr_stretch_names, picture.stretch.kind)},
    {.key = "output.white", .type = K_AUTO, FIELD(picture.stretch.white), ABOVE(0)},
    {.key = "output.white_percentile", .type = K_NUMBER, FIELD(picture.stretch.white_percentile), .lo = 0,
     .hi = 100, .bounds = HAS_LO | LO_OPEN | HAS_HI},
    {.key = "output.softening", .type = K_NUMBER, FIELD(picture.stretch.n), ABOVE(0)},
    {.key = "output.colormap", NAMED(orr_colormap_kind_names, picture.colormap)},
    {.key = "output.bunit", .type = K_STRING, FIELD(output.bunit)},
    {.key = "output.length_unit", .type = K_STRING, FIELD(output.length_unit)},
    {.key = "output.frame_start", .type = K_LLONG, FIELD(output.frame_start), IRANGE(0, 1000000000LL)},
    {.key = "output.frame_digits", .type = K_INT, FIELD(output.frame_digits), IRANGE(1, 18)},
    {.key = "output.frame_separator", .type = K_STRING, FIELD(output.frame_separator)},
    {.key = "output.alpha_mask", .type = K_BOOL, FIELD(output.alpha_mask)},
};

/* The keys of a dome profile (domes/NAME.yaml). */
static const key_spec PROFILE_KEYS[] = {
    {.key = "description", .type = K_STRING, FIELD_OF(dome_profile, description)},
    {.key = "fov", .type = K_NUMBER, FIELD_OF(dome_profile, fov), CLOSED(90, 360), FLAG_OF(dome_profile, has_fov)},
    {.key = "tilt", .type = K_NUMBER, FIELD_OF(dome_profile, tilt), CLOSED(0, 90), FLAG_OF(dome_profile, has_tilt)},
    {.key = "size", .type = K_INT, FIELD_OF(dome_profile, size), IRANGE(1, ORR_IMAGE_SIDE_MAX),
     FLAG_OF(dome_profile, has_size)},
};

#define NKEYS (sizeof KEYS / sizeof KEYS[0])
_Static_assert(NKEYS <= SCENE_MAX_KEYS, "scene_marks has room for every key");
_Static_assert(sizeof PROFILE_KEYS / sizeof PROFILE_KEYS[0] <= SCENE_MAX_KEYS, "and every profile key");

const key_table scene_key_table = {KEYS, NKEYS, "docs/scenes.md"};
const key_table scene_profile_key_table = {PROFILE_KEYS, sizeof PROFILE_KEYS / sizeof PROFILE_KEYS[0],
                                           "domes/README.md"};

/* ---- finding keys ---- */

const key_spec *scene_find_key(const key_table *t, const char *path)
{
    for (size_t i = 0; i < t->n; i++)
        if (strcmp(t->keys[i].key, path) == 0)
            return &t->keys[i];
    return NULL;
}

int scene_is_section(const key_table *t, const char *path)
{
    size_t len = strlen(path);
    for (size_t i = 0; i < t->n; i++)
        if (strncmp(t->keys[i].key, path, len) == 0 && t->keys[i].key[len] == '.')
            return 1;
    return 0;
}

const scene_loc *scene_mark(const scene_marks *marks, const char *key)
{
    const key_spec *k = scene_find_key(&scene_key_table, key);
    if (!k)
        return NULL;
    const scene_loc *loc = &marks->loc[k - KEYS];
    return loc->origin ? loc : NULL;
}

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

/* Within two edits, or else the only key with the same last part
 * ("camera.height" -> "image.height"). */
void scene_suggest_key(const key_table *t, const char *path, char *buf, size_t size)
{
    int best = 3;
    buf[0] = '\0';
    for (size_t i = 0; i < t->n; i++) {
        char cand[SCENE_KEY_PATH_MAX];
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
