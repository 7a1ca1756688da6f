#include "frame/stereo.h"

#include <math.h>
#include <string.h>

const orr_named orr_stereo_mode_names[] = {{"none", ORR_STEREO_NONE},
                                           {"anaglyph", ORR_STEREO_ANAGLYPH},
                                           {"side-by-side", ORR_STEREO_SIDE_BY_SIDE},
                                           {"over-under", ORR_STEREO_OVER_UNDER},
                                           {"separate", ORR_STEREO_SEPARATE},
                                           {NULL, 0}};

void orr_stereo_settings_defaults(orr_stereo_settings *d)
{
    memset(d, 0, sizeof *d);
    d->mode = ORR_STEREO_NONE;
    d->eye_separation = 0;
    d->convergence = 0; /* auto */
    d->zenith_fade = 0;
    d->eye = 0;
}

static orr_status check_without_stereo(const orr_keys *keys, orr_error *err)
{
    static const char *const pair_keys[] = {"stereo.eye_separation", "stereo.convergence", "stereo.anaglyph",
                                            "stereo.zenith_fade"};
    for (size_t i = 0; i < sizeof pair_keys / sizeof pair_keys[0]; i++)
        if (orr_key_given(keys, pair_keys[i]))
            return orr_fail_key(keys, pair_keys[i], err, "%s applies to stereo, but stereo.mode is none",
                                pair_keys[i]);
    return ORR_OK;
}

orr_status orr_stereo_prepare(const orr_stereo_settings *st, orr_projection_kind kind, const orr_keys *keys,
                              orr_error *err)
{
    if (st->mode == ORR_STEREO_NONE)
        return check_without_stereo(keys, err);
    const char *mode = orr_stereo_mode_name(st->mode);
    if (kind == ORR_PROJ_ORTHOGRAPHIC)
        return orr_fail_key(keys, "stereo.mode", err,
                            "stereo.mode: %s needs parallax, which an orthographic camera has none of; use "
                            "camera.projection: perspective (or a sky map for omni-directional stereo)",
                            mode);
    if (!orr_key_given(keys, "stereo.eye_separation"))
        return orr_fail_key(keys, "stereo.mode", err,
                            "stereo.mode: %s needs stereo.eye_separation, the distance between the eyes in "
                            "scene units",
                            mode);
    if (st->mode != ORR_STEREO_ANAGLYPH && orr_key_given(keys, "stereo.anaglyph"))
        return orr_fail_key(keys, "stereo.anaglyph", err, "stereo.anaglyph applies to stereo.mode: anaglyph, not %s",
                            mode);
    if (kind == ORR_PROJ_PERSPECTIVE && orr_key_given(keys, "stereo.zenith_fade"))
        return orr_fail_key(keys, "stereo.zenith_fade", err,
                            "stereo.zenith_fade is for omni-directional stereo (dome, equirectangular, "
                            "hammer-aitoff), not a perspective camera");
    if (kind != ORR_PROJ_PERSPECTIVE && orr_key_given(keys, "stereo.convergence"))
        return orr_fail_key(keys, "stereo.convergence", err,
                            "stereo.convergence is for a perspective camera; omni-directional stereo (%s) has "
                            "its zero parallax at infinity",
                            orr_projection_name(kind));
    return ORR_OK;
}

void orr_stereo_cards(const orr_stereo_settings *st, orr_projection_kind kind, orr_cards *h)
{
    orr_cards_add_string(h, "STEREO", orr_stereo_mode_name(st->mode), "stereo mode");
    if (st->mode == ORR_STEREO_SEPARATE && st->eye)
        orr_cards_add_string(h, "EYE", orr_eye_name(st->eye), "the eye of this file");
    else
        orr_cards_add_string(h, "EYES", "left, right", "HDUs: the left eye's planes, then the right's");
    orr_cards_add_double(h, "EYESEP", st->eye_separation, "interocular distance, scene units");
    if (orr_projection_traits_of(kind).off_axis_stereo)
        orr_cards_reserve(h, "CONVERG", "distance of zero parallax, scene units"); /* the frame's */
    else
        orr_cards_add_double(h, "ZENFADE", st->zenith_fade, "[deg] ODS separation fades to 0 at the pole");
}

const char *orr_stereo_mode_name(orr_stereo_mode mode) { return orr_named_name(orr_stereo_mode_names, (int)mode); }

ORR_NAMED_PARSER(orr_stereo_mode_from_name, orr_stereo_mode, orr_stereo_mode_names)

const char *orr_eye_name(int eye) { return eye < 0 ? "left" : "right"; }

orr_status orr_stereo_perspective_eye(orr_camera *cam, orr_projection *proj, int eye, double separation,
                                      double convergence, orr_error *err)
{
    if (proj->settings.kind != ORR_PROJ_PERSPECTIVE)
        return orr_fail(err, ORR_ERR_USAGE, "a stereo pair of cameras needs the perspective projection, not %s",
                        orr_projection_name(proj->settings.kind));
    if (!(separation > 0) || !isfinite(separation))
        return orr_fail(err, ORR_ERR_USAGE, "stereo eye separation %g must be a positive number", separation);
    if (!(convergence > 0) || !isfinite(convergence))
        return orr_fail(err, ORR_ERR_USAGE, "stereo convergence distance %g must be a positive number",
                        convergence);
    /* The camera's right axis in world coordinates: the first column of
     * the camera-to-world rotation. */
    orr_vec3 right = orr_quat_rotate(cam->orientation, orr_v3(1, 0, 0));
    cam->position = orr_v3_add(cam->position, orr_v3_scale(right, eye * 0.5 * separation));
    /* In the eye's frame a point on the central axis at distance C sits at
     * x = -eye * separation / 2, which projects -eye * focal * separation /
     * (2 C) pixels from the principal point: shifting the principal point
     * by the opposite brings it back to the image centre in both eyes. */
    orr_projection_settings shifted = proj->settings;
    shifted.shift_x = eye * proj->focal * 0.5 * separation / convergence;
    orr_status st = orr_projection_check(&shifted, err); /* a shift too large to be a number */
    return st ? st : orr_projection_plan(proj, &shifted, err);
}

orr_status orr_stereo_ods_setup(orr_stereo_ods *ods, const orr_projection *proj, int eye, double separation,
                                double zenith_fade_deg, orr_error *err)
{
    if (!orr_projection_is_sky(proj))
        return orr_fail(err, ORR_ERR_USAGE, "omni-directional stereo needs a sky projection, not %s",
                        orr_projection_name(proj->settings.kind));
    if (!(separation > 0) || !isfinite(separation))
        return orr_fail(err, ORR_ERR_USAGE, "stereo eye separation %g must be a positive number", separation);
    if (!(zenith_fade_deg >= 0 && zenith_fade_deg <= 90))
        return orr_fail(err, ORR_ERR_USAGE, "stereo zenith fade %g degrees must lie between 0 and 90",
                        zenith_fade_deg);
    ods->eye = eye < 0 ? ORR_EYE_LEFT : ORR_EYE_RIGHT;
    ods->side = proj->settings.kind != ORR_PROJ_DOME && proj->settings.lon_flip ? -ods->eye : ods->eye;
    ods->pole_is_z = proj->settings.kind == ORR_PROJ_DOME;
    ods->radius = (float)(0.5 * separation);
    ods->inv_sin_fade = zenith_fade_deg > 0 ? (float)(1.0 / sin(zenith_fade_deg * ORR_PI / 180.0)) : 0.0f;
    return ORR_OK;
}

/* The transform in the horizontal plane's coordinates (a, b) with the pole
 * coordinate c; for both kinds of map the horizontal direction to the
 * right of (a, b), seen from above, is (b, -a) (dome: (x, y) x z; sky maps:
 * (x, z) x up, up = -y).
 *
 * With q = (a, b), rho = |q| and r the eye radius, the eye whose tangent
 * ray passes through q is e = (r^2 / rho^2) q + eye * r sqrt(rho^2 - r^2) /
 * rho^2 * (b, -a): e is on the circle and perpendicular to q - e. A point
 * straight ahead at distance d is then seen asin(r / d) to the right in the
 * left eye and to the left in the right eye. */
static inline size_t ods_plane(const orr_stereo_ods *ods, size_t n, float *restrict a, float *restrict b,
                               const float *restrict c, uint8_t *restrict keep, const int fade)
{
    const float r0 = ods->radius, side = (float)ods->side, inv_sin_fade = ods->inv_sin_fade;
    unsigned skipped = 0;
    /* Selects, not branches, so the loop vectorises (fade is a constant in
     * each of the two copies below). */
    for (size_t i = 0; i < n; i++) {
        const float ai = a[i], bi = b[i], ci = c[i];
        const float rho2 = ai * ai + bi * bi;
        float r = r0;
        if (fade) /* sin(angle from the pole) = rho / |p| */
            r = r0 * fminf(1.0f, sqrtf(rho2 / (rho2 + ci * ci + 1e-30f)) * inv_sin_fade);
        const float r2 = r * r;
        const int inside = rho2 < r2;
        /* With a fade the circle shrinks to a point on the pole axis, where
         * rho2 = r2 = 0: that eye sits at the centre (e = 0). */
        const float inv_rho2 = inside || rho2 == 0.0f ? 0.0f : 1.0f / rho2;
        const float along = r2 * inv_rho2;
        const float across = side * r * sqrtf(inside ? 0.0f : rho2 - r2) * inv_rho2;
        a[i] = ai - (along * ai + across * bi);
        b[i] = bi - (along * bi - across * ai);
        keep[i] = (uint8_t)!inside;
        skipped += (unsigned)inside;
    }
    return skipped;
}

static size_t ods_block(const orr_stereo_ods *ods, size_t n, float *a, float *b, const float *c, uint8_t *keep)
{
    return ods->inv_sin_fade > 0.0f ? ods_plane(ods, n, a, b, c, keep, 1) : ods_plane(ods, n, a, b, c, keep, 0);
}

size_t orr_stereo_ods_apply(const orr_stereo_ods *ods, size_t n, float *x, float *y, float *z, uint8_t *keep)
{
    return ods->pole_is_z ? ods_block(ods, n, x, y, z, keep) : ods_block(ods, n, x, z, y, keep);
}

void orr_stereo_mask(size_t n, uint8_t *visible, const uint8_t *keep)
{
    for (size_t i = 0; i < n; i++)
        visible[i] &= keep[i];
}
