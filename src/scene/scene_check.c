/* A bound scene checked: each stage checks its own keys (orr_X_prepare,
 * given where each key was set, core/keys.h), called here in turn; what is
 * left here are the rules that span stages, each saying which, and what
 * the scene alone records (its settings' text and digest, its YAML). */
#define _XOPEN_SOURCE 700 /* realpath (XSI) */
#include "scene/scene_check.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/digest.h"

#include "scene/scene_bind.h"
#include "scene/scene_dome.h"
#include "scene/scene_output.h"
#include "scene/scene_path.h"
#include "scene/ytree.h"

#define COUNT(a) (sizeof(a) / sizeof((a)[0]))

/* ---- observer and camera ---- */

/* The camera keys the observer particle replaces. */
static const char *const PLACEMENT_KEYS[] = {"camera.position", "camera.look_at", "camera.direction",
                                             "camera.quaternion"};

/* camera.dim dims from any camera; with an observer, observer.dim does
 * that already, and two switches for one thing would only confuse (spans
 * the camera and the observer). */
static orr_status check_camera_dim(const orr_scene *s, const scene_marks *m, orr_error *err)
{
    if (s->observer.has_id && scene_mark(m, "camera.dim"))
        return scene_fail_key(s, m, "camera.dim", err,
                              "camera.dim is not allowed with observer.id: use observer.dim for an observer's sky");
    return ORR_OK;
}

/* The observer's keys are the observer's (frame/observer.h); with an
 * observer, the camera keys it replaces span the two. */
static orr_status check_observer(const orr_scene *s, const scene_marks *m, const orr_keys *keys, orr_error *err)
{
    orr_status st = check_camera_dim(s, m, err);
    if (!st)
        st = orr_observer_prepare(&s->observer, keys, err);
    for (size_t i = 0; !st && s->observer.has_id && i < COUNT(PLACEMENT_KEYS); i++)
        if (scene_mark(m, PLACEMENT_KEYS[i]))
            return scene_fail_key(s, m, PLACEMENT_KEYS[i], err,
                                  "%s is not allowed with observer.id: the observer particle places and orients "
                                  "the camera",
                                  PLACEMENT_KEYS[i]);
    return st;
}

/* Smoothing the automatic white over frames re-grades each frame's picture
 * from its FITS planes once the run is rendered (spans the run, the
 * grading, the outputs and stereo). */
static orr_status check_white_smoothing(const orr_scene *s, const scene_marks *m, orr_error *err)
{
    if (s->animation.white_smoothing == 0)
        return ORR_OK;
    int graded_by_synthesis = s->colour.has_populations || s->compose.nlayers || s->colour.has_tint;
    const char *white_key = graded_by_synthesis ? "colour.synthesis.white" : "output.white";
    if ((graded_by_synthesis ? s->colour.synth.y0 : s->picture.stretch.white) > 0)
        return scene_fail_key(s, m, "animation.white_smoothing", err,
                              "animation.white_smoothing averages the automatic white level, but %s is fixed: "
                              "set %s: auto, or leave out the smoothing",
                              white_key, white_key);
    if (!s->output.write_fits)
        return scene_fail_key(s, m, "animation.white_smoothing", err,
                              "animation.white_smoothing re-grades each frame from its FITS planes: it needs "
                              "output.fits: true");
    if (s->stereo.mode != ORR_STEREO_NONE)
        return scene_fail_key(s, m, "animation.white_smoothing", err,
                              "animation.white_smoothing cannot yet be combined with stereo.mode");
    return ORR_OK;
}

/* ---- stereo ---- */

/* A perspective pair converges where stereo.convergence says, or by
 * default on the point the camera looks at (spans the stereo pair and the
 * camera). */
static orr_status check_convergence(const orr_scene *s, const scene_marks *m, orr_error *err)
{
    orr_vec3 target;
    if (s->stereo.mode == ORR_STEREO_NONE || s->projection.kind != ORR_PROJ_PERSPECTIVE ||
        s->stereo.convergence > 0 || orr_scene_look_target(s, &target)) /* auto: at render time, to the target */
        return ORR_OK;
    return scene_fail_key(s, m, "stereo.mode", err,
                          "stereo.mode: %s with a perspective camera needs stereo.convergence (the distance of "
                          "the zero-parallax plane) or a point the camera looks at (camera.look_at, or an orbit "
                          "or inspiral path's centre: converge there)",
                          orr_stereo_mode_name(s->stereo.mode));
}

/* The stereo pair's keys are the pair's (frame/stereo.h); what it cannot
 * be combined with yet spans it and the outputs. */
static orr_status check_stereo(const orr_scene *s, const scene_marks *m, const orr_keys *keys, orr_error *err)
{
    orr_status st = orr_stereo_prepare(&s->stereo, s->projection.kind, keys, err);
    if (st || s->stereo.mode == ORR_STEREO_NONE)
        return st;
    if (s->output.write_raw || s->compose.nlayers)
        return scene_fail_key(s, m, "stereo.mode", err,
                              "stereo.mode: %s cannot yet be combined with %s (orrery compose works on one "
                              "eye's planes)",
                              orr_stereo_mode_name(s->stereo.mode),
                              s->output.write_raw ? "output.raw" : "compose.layers");
    return check_convergence(s, m, err);
}

/* The settings text and its digest: the tree's keys, then what the dome
 * profile (a file of its own) put into the scene. */
static orr_status record_settings(orr_scene *s, const yt_node *root, orr_error *err)
{
    char *text = yt_settings_text(root, err);
    if (!text)
        return ORR_ERR_NOMEM;
    char profile[256] = "";
    if (s->camera.dome[0])
        snprintf(profile, sizeof profile, "(dome profile %s)=fov %.17g, tilt %.17g, size %dx%d\n", s->camera.dome,
                 s->projection.dome_fov_deg, s->camera.dome_tilt, s->projection.width, s->projection.height);
    s->settings_digest = orr_digest_text(orr_digest_text(ORR_DIGEST_START, text), profile);
    snprintf(s->settings, sizeof s->settings, "%s%s", text, profile);
    free(text);
    return ORR_OK;
}

/* The folder a scene's relative file names are resolved against, absolute
 * where it can be, on one line. */
static void scene_folder(const orr_scene *s, char *out, size_t size)
{
    char *abs = realpath(s->dir, NULL);
    snprintf(out, size, "%s", abs ? abs : s->dir);
    free(abs);
    for (char *c = out; *c; c++)
        if ((unsigned char)*c < 0x20 || *c == 0x7f)
            *c = '?';
}

/* The effective keys as YAML, for the SCENE extension of the FITS outputs,
 * after a comment saying how to use it. Left empty when it does not fit:
 * a scene cut short would render something else. */
static orr_status record_scene_yaml(orr_scene *s, const yt_node *root, orr_error *err)
{
    char *yaml = yt_yaml_text(root, err);
    if (!yaml)
        return ORR_ERR_NOMEM;
    char folder[ORR_PATH_MAX];
    scene_folder(s, folder, sizeof folder);
    int n = snprintf(s->scene_yaml, sizeof s->scene_yaml,
                     "# The scene this file was rendered from by orrery %s: the scene file with the\n"
                     "# command line's --set overrides applied (and its view's keys merged in).\n"
                     "# orrery render of this text draws the same planes; its relative file names\n"
                     "# are relative to %s\n%s",
                     ORRERY_VERSION, folder, yaml);
    if (n < 0 || (size_t)n >= sizeof s->scene_yaml)
        s->scene_yaml[0] = '\0';
    free(yaml);
    return ORR_OK;
}

/* Dust: the stage's own checks (given the drawn types), and what it cannot
 * do yet with a periodic box's copies and a HEALPix map (spans the dust,
 * the frame and the outputs). */
static orr_status check_dust(const orr_scene *s, orr_error *err)
{
    orr_status st = orr_dust_settings_check(&s->dust, s->path, s->input.type_mask, err);
    if (!st && s->dust.types && s->periodic.replicas > 1)
        st = orr_fail(err, ORR_ERR_USAGE, "%s: dust.types with input.periodic.replicas: the dust of a replicated "
                      "box is not replicated yet (docs/dust.md#limitations)", s->path);
    if (!st && s->dust.types && s->dust.extinction_plane && s->projection.kind == ORR_PROJ_HEALPIX)
        st = orr_fail(err, ORR_ERR_USAGE, "%s: dust.extinction_plane is not written for camera.projection: "
                      "healpix yet (docs/dust.md#limitations)", s->path);
    return st;
}

/* Stars spawned from the particles (stars.limit) need what they are
 * drawn from and seen by: the observer (their magnitudes are from its
 * place), colour populations (their light is split off the particles'
 * X, Y, Z), and particles of the spawning types drawn (spans the stars,
 * the observer, the colours, the glow and the input). */
static orr_status check_stars(const orr_scene *s, orr_error *err)
{
    const orr_stars_settings *st = &s->stars;
    if (!st->enabled)
        return ORR_OK;
    if (!s->observer.has_id)
        return orr_fail(err, ORR_ERR_USAGE, "%s: stars.limit: stars are spawned as an observer sees them; give "
                        "observer.id", s->path);
    if (!s->colour.has_populations)
        return orr_fail(err, ORR_ERR_USAGE, "%s: stars.limit: the stars take their light from the particles' "
                        "colour populations; give colour.populations", s->path);
    if (!st->types)
        return orr_fail(err, ORR_ERR_USAGE, "%s: stars.limit: give stars.types, the particle types that spawn "
                        "stars", s->path);
    /* What the stars leave glows from each particle's neighbours on the sky. */
    if (!s->psf.has_glow)
        return orr_fail(err, ORR_ERR_USAGE, "%s: stars.limit: what the stars leave of their particles' light is "
                        "drawn as a glow: give glow.threshold (a sky map with a psf.kind)", s->path);
    if (st->types & ~s->input.type_mask)
        return orr_fail(err, ORR_ERR_USAGE, "%s: stars.types: every type that spawns stars must be drawn "
                        "(input.types)", s->path);
    if (s->periodic.replicas > 1 || s->output.exr_population_layers)
        return orr_fail(err, ORR_ERR_USAGE, "%s: stars.limit: not with %s yet", s->path,
                        s->periodic.replicas > 1 ? "input.periodic.replicas" : "output.exr_population_layers");
    return ORR_OK;
}

orr_status scene_bind_checked(orr_scene *s, const yt_node *root, orr_error *err)
{
    scene_marks marks;
    orr_status st = scene_bind(s, root, &marks, err);
    scene_keyed where = {s, &marks};
    orr_keys keys = scene_keys(&where);
    if (st == ORR_OK)
        st = orr_input_prepare(&s->input, &keys, err);
    if (st == ORR_OK)
        st = orr_periodic_prepare(&s->periodic, &keys, err);
    if (st == ORR_OK) /* before the camera: its placement keys are not allowed with an observer */
        st = check_observer(s, &marks, &keys, err);
    if (st == ORR_OK) /* before the camera: a path excludes its placement keys */
        st = scene_check_path(s, &marks, err);
    if (st == ORR_OK)
        st = orr_camera_settings_prepare(&s->camera, &keys, err);
    if (st == ORR_OK)
        st = scene_apply_dome_profile(s, &marks, err);
    if (st == ORR_OK)
        st = scene_check_healpix(s, &marks, err);
    if (st == ORR_OK)
        st = orr_projection_prepare(&s->projection, &keys, err);
    if (st == ORR_OK) /* the PSF's keys, given the map they are for */
        st = orr_psf_prepare(&s->psf, orr_projection_traits_of(s->projection.kind).sky, &keys, err);
    if (st == ORR_OK)
        st = orr_colour_prepare(&s->colour, &keys, err);
    if (st == ORR_OK)
        st = check_dust(s, err);
    if (st == ORR_OK)
        st = check_stars(s, err);
    if (st == ORR_OK)
        st = orr_output_prepare(&s->output, &keys, err);
    if (st == ORR_OK)
        st = scene_check_output_keys(s, &marks, err);
    if (st == ORR_OK)
        st = check_stereo(s, &marks, &keys, err);
    if (st == ORR_OK)
        st = check_white_smoothing(s, &marks, err);
    if (st == ORR_OK)
        st = record_settings(s, root, err);
    if (st == ORR_OK)
        st = record_scene_yaml(s, root, err);
    return st;
}
