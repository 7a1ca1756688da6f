/* Stereo: the eyes of a perspective pair sit where they should and converge
 * where they should (zero parallax at the convergence distance, crossed
 * nearer, uncrossed farther, never vertical); omni-directional stereo turns
 * a point at distance d by the analytic asin(r / d) in azimuth, each eye
 * its own way, and skips what is inside the eye circle; anaglyphs take
 * each channel from the right eye; a pair's picture lays the eyes out as
 * named; the stereo.* keys are validated. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "planned.h"
#include "frame/stereo.h"
#include "post/anaglyph.h"
#include "render/stereo_view.h"
#include "scene/scene.h"

#define DEG (ORR_PI / 180.0)

/* ---- perspective pairs ---- */

typedef struct eye_view {
    orr_camera cam;
    orr_projection proj;
} eye_view;

/* A 200 x 100 perspective camera at (1, 2, 3) looking along +x with +z up
 * (so its right axis is -y), moved to one eye. */
static eye_view perspective_eye(int eye, double separation, double convergence)
{
    eye_view v;
    orr_error err = {0};
    v.proj = PLANNED(.kind = ORR_PROJ_PERSPECTIVE, .width = 200, .height = 100, .fov_deg = 60, .near = 1e-3);
    CHECK(orr_camera_look_along(&v.cam, orr_v3(1, 2, 3), orr_v3(1, 0, 0), orr_v3(0, 0, 1), 0, &err) == ORR_OK);
    CHECK(orr_stereo_perspective_eye(&v.cam, &v.proj, eye, separation, convergence, &err) == ORR_OK);
    return v;
}

/* Where eye v draws the world point w. */
static void draw(const eye_view *v, orr_vec3 w, double *px, double *py)
{
    orr_mat3 m = orr_camera_world_to_camera(&v->cam);
    orr_vec3 c = orr_mat3_apply(m, orr_v3_sub(w, v->cam.position));
    double s;
    CHECK(orr_project_point(&v->proj, c, px, py, &s) == 1);
}

static void test_perspective_eye_offsets(void)
{
    eye_view l = perspective_eye(ORR_EYE_LEFT, 0.4, 10), r = perspective_eye(ORR_EYE_RIGHT, 0.4, 10);
    /* Looking along +x with +z up, right is -y: the left eye is at +y. */
    CHECK_NEAR(l.cam.position.x, 1, 1e-12);
    CHECK_NEAR(l.cam.position.y, 2.2, 1e-12);
    CHECK_NEAR(l.cam.position.z, 3, 1e-12);
    CHECK_NEAR(r.cam.position.y, 1.8, 1e-12);
    /* Parallel axes: both eyes keep the centre camera's orientation. */
    CHECK_NEAR(l.cam.orientation.w, r.cam.orientation.w, 1e-15);
    CHECK_NEAR(l.cam.orientation.z, r.cam.orientation.z, 1e-15);
    /* The principal point moves by focal * separation / (2 C), each eye its way. */
    double f = 100 / tan(30 * DEG);
    CHECK_NEAR(l.proj.cx, 100 - f * 0.2 / 10, 1e-9);
    CHECK_NEAR(r.proj.cx, 100 + f * 0.2 / 10, 1e-9);
    CHECK_NEAR(l.proj.cy, 50, 1e-12);
}

static void test_perspective_parallax(void)
{
    const double sep = 0.4, conv = 10, f = 100 / tan(30 * DEG);
    eye_view l = perspective_eye(ORR_EYE_LEFT, sep, conv), r = perspective_eye(ORR_EYE_RIGHT, sep, conv);
    double lx, ly, rx, ry;
    /* On the view axis at the convergence distance: the same pixel, the image centre. */
    draw(&l, orr_v3(1 + conv, 2, 3), &lx, &ly);
    draw(&r, orr_v3(1 + conv, 2, 3), &rx, &ry);
    CHECK_NEAR(lx, 100, 1e-9);
    CHECK_NEAR(rx, 100, 1e-9);
    /* Anywhere on the convergence plane: zero parallax too. */
    draw(&l, orr_v3(1 + conv, 0.5, 4), &lx, &ly);
    draw(&r, orr_v3(1 + conv, 0.5, 4), &rx, &ry);
    CHECK_NEAR(lx - rx, 0, 1e-9);
    CHECK_NEAR(ly - ry, 0, 1e-9);
    /* Nearer: crossed, further right in the left eye, by f sep (1/z - 1/C). */
    draw(&l, orr_v3(1 + 4, 2, 3), &lx, &ly);
    draw(&r, orr_v3(1 + 4, 2, 3), &rx, &ry);
    CHECK(lx > rx);
    CHECK_NEAR(lx - rx, f * sep * (1.0 / 4 - 1.0 / conv), 1e-9);
    CHECK_NEAR(ly - ry, 0, 1e-9); /* no vertical parallax */
    /* Farther: uncrossed, tending to f sep / C at infinity. */
    draw(&l, orr_v3(1 + 40, 1, 2), &lx, &ly);
    draw(&r, orr_v3(1 + 40, 1, 2), &rx, &ry);
    CHECK(lx < rx);
    CHECK_NEAR(lx - rx, f * sep * (1.0 / 40 - 1.0 / conv), 1e-9);
    CHECK_NEAR(ly - ry, 0, 1e-9);
}

static void test_perspective_eye_rejects_bad_input(void)
{
    orr_error err = {0};
    orr_camera cam = {orr_v3(0, 0, 0), {1, 0, 0, 0}};
    orr_projection p = PLANNED(.kind = ORR_PROJ_PERSPECTIVE, .width = 10, .height = 10, .fov_deg = 60);
    CHECK(orr_stereo_perspective_eye(&cam, &p, ORR_EYE_LEFT, 0, 10, &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "separation");
    CHECK(orr_stereo_perspective_eye(&cam, &p, ORR_EYE_LEFT, 1, NAN, &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "convergence");
    p = PLANNED(.kind = ORR_PROJ_ORTHOGRAPHIC, .width = 10, .height = 10, .ortho_width = 1);
    CHECK(orr_stereo_perspective_eye(&cam, &p, ORR_EYE_LEFT, 1, 10, &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "orthographic");
}

/* ---- omni-directional stereo ---- */

static orr_projection sky(orr_projection_kind kind, int w, int h)
{
    return PLANNED(.kind = kind, .width = w, .height = h, .dome_fov_deg = 180);
}

static orr_stereo_ods ods_eye(const orr_projection *p, int eye, double separation, double fade)
{
    orr_stereo_ods o;
    orr_error err = {0};
    CHECK(orr_stereo_ods_setup(&o, p, eye, separation, fade, &err) == ORR_OK);
    return o;
}

/* Moves one point by an ODS eye; returns keep. */
static int ods_point(const orr_stereo_ods *o, float *x, float *y, float *z)
{
    uint8_t keep = 7;
    size_t skipped = orr_stereo_ods_apply(o, 1, x, y, z, &keep);
    CHECK(skipped == (keep ? 0u : 1u));
    return keep;
}

static void test_ods_equirectangular_ahead(void)
{
    /* 3600 x 1800: ten pixels a degree. */
    orr_projection p = sky(ORR_PROJ_EQUIRECTANGULAR, 3600, 1800);
    const double d = 5, ipd = 1, expect = asin(ipd / 2 / d);
    for (int eye = -1; eye <= 1; eye += 2) {
        orr_stereo_ods o = ods_eye(&p, eye, ipd, 0);
        float x = 0, y = 0, z = (float)d;
        CHECK(ods_point(&o, &x, &y, &z) == 1);
        /* Seen from the eye: turned by asin(r / d), to the right (+x) in
         * the left eye, to the left in the right eye, and still level. */
        CHECK_NEAR(atan2(x, z), -eye * expect, 1e-6);
        CHECK_NEAR(y, 0, 1e-7);
        double px, py, s;
        CHECK(orr_project_point(&p, orr_v3(x, y, z), &px, &py, &s) == 1);
        CHECK_NEAR(px - p.cx, -eye * expect / DEG * 10, 1e-3);
        CHECK_NEAR(py, p.cy, 1e-4);
        /* The eye is on the circle, and its ray to the point is tangent to it. */
        double ex = 0 - x, ez = d - z;
        CHECK_NEAR(sqrt(ex * ex + ez * ez), ipd / 2, 1e-6);
        CHECK_NEAR(ex * x + ez * z, 0, 1e-5);
    }
}

/* A mirrored map (lon_flip) keeps the left eye's near point to the right
 * in the picture: the depth does not turn inside out. */
static void test_ods_mirrored_map(void)
{
    for (int flip = 0; flip <= 1; flip++) {
        orr_projection p = PLANNED(.kind = ORR_PROJ_EQUIRECTANGULAR, .width = 360, .height = 180, .lon_flip = flip);
        orr_stereo_ods l = ods_eye(&p, ORR_EYE_LEFT, 1, 0);
        float x = 0, y = 0, z = 5;
        CHECK(ods_point(&l, &x, &y, &z) == 1);
        double px, py, s;
        CHECK(orr_project_point(&p, orr_v3(x, y, z), &px, &py, &s) == 1);
        CHECK_NEAR(px - p.cx, asin(0.1) / DEG, 1e-3);
    }
}

static void test_ods_dome_horizon_and_zenith(void)
{
    orr_projection p = sky(ORR_PROJ_DOME, 1000, 1000);
    const double d = 8, ipd = 2, expect = asin(ipd / 2 / d);
    /* On the dome the horizontal plane is x, y (z is the zenith); the front
     * (+y, the bottom of the master) seen by the left eye turns right (+x). */
    orr_stereo_ods l = ods_eye(&p, ORR_EYE_LEFT, ipd, 0), r = ods_eye(&p, ORR_EYE_RIGHT, ipd, 0);
    float x = 0, y = (float)d, z = 0;
    CHECK(ods_point(&l, &x, &y, &z) == 1);
    CHECK_NEAR(atan2(x, y), expect, 1e-6);
    CHECK_NEAR(z, 0, 0);
    x = 0, y = (float)d, z = 0;
    CHECK(ods_point(&r, &x, &y, &z) == 1);
    CHECK_NEAR(atan2(x, y), -expect, 1e-6);
    /* Height does not change the eye: a point 30 degrees up keeps its
     * height and turns by asin(r / rho) with rho its horizontal distance. */
    x = 0, y = (float)d, z = (float)(d * tan(30 * DEG));
    CHECK(ods_point(&l, &x, &y, &z) == 1);
    CHECK_NEAR(z, d * tan(30 * DEG), 1e-5);
    CHECK_NEAR(atan2(x, y), expect, 1e-6);
    /* The zenith is inside every eye circle: skipped, coordinates untouched. */
    x = 0, y = 0, z = 10;
    CHECK(ods_point(&l, &x, &y, &z) == 0);
    CHECK(x == 0 && y == 0 && z == 10);
}

static void test_ods_skips_inside_eye_circle(void)
{
    orr_projection p = sky(ORR_PROJ_HAMMER_AITOFF, 400, 200);
    orr_stereo_ods o = ods_eye(&p, ORR_EYE_RIGHT, 1, 0); /* radius 0.5 */
    /* Sky maps: the horizontal plane is x, z. */
    float x[5] = {0.1f, 0.3f, 0.0f, 2.0f, 0.3f}, y[5] = {0, 5, -9, 0, 0}, z[5] = {0.1f, 0.3f, 0.49f, 0, 0.5f};
    const float x0[5] = {0.1f, 0.3f, 0.0f, 2.0f, 0.3f};
    uint8_t keep[5];
    CHECK(orr_stereo_ods_apply(&o, 5, x, y, z, keep) == 3);
    CHECK(keep[0] == 0 && keep[1] == 0 && keep[2] == 0); /* horizontal distance < 0.5, whatever the height */
    CHECK(keep[3] == 1 && keep[4] == 1);
    CHECK(x[0] == x0[0] && x[1] == x0[1] && z[2] == 0.49f);
    CHECK(x[3] != x0[3] || z[3] != 0);
    /* The render masks them: visible &= keep. */
    uint8_t visible[5] = {1, 1, 1, 1, 0};
    orr_stereo_mask(5, visible, keep);
    CHECK(visible[0] == 0 && visible[2] == 0 && visible[3] == 1 && visible[4] == 0);
}

static void test_ods_zenith_fade(void)
{
    orr_projection p = sky(ORR_PROJ_DOME, 500, 500);
    const double ipd = 1, rho = 4;
    /* A 90-degree fade scales the separation by sin(angle from the zenith):
     * at 60 degrees from the zenith the radius is 0.5 sin 60. */
    orr_stereo_ods o = ods_eye(&p, ORR_EYE_LEFT, ipd, 90);
    float x = 0, y = (float)rho, z = (float)(rho / tan(60 * DEG));
    CHECK(ods_point(&o, &x, &y, &z) == 1);
    CHECK_NEAR(atan2(x, y), asin(0.5 * sin(60 * DEG) / rho), 1e-6);
    /* A 30-degree fade leaves the horizon alone but fades a point 15
     * degrees from the zenith to sin 15 / sin 30 of the radius. */
    o = ods_eye(&p, ORR_EYE_LEFT, ipd, 30);
    x = 0, y = (float)rho, z = 0;
    CHECK(ods_point(&o, &x, &y, &z) == 1);
    CHECK_NEAR(atan2(x, y), asin(0.5 / rho), 1e-6);
    x = 0, y = (float)rho, z = (float)(rho / tan(15 * DEG));
    CHECK(ods_point(&o, &x, &y, &z) == 1);
    CHECK_NEAR(atan2(x, y), asin(0.5 * sin(15 * DEG) / sin(30 * DEG) / rho), 1e-6);
    /* With the fade, a point on the zenith axis is drawn where it is. */
    x = 0, y = 0, z = 10;
    CHECK(ods_point(&o, &x, &y, &z) == 1);
    CHECK(x == 0 && y == 0 && z == 10);
    /* With the fade, a point near the zenith axis is drawn, barely moved. */
    x = 0.01f, y = 0, z = 10;
    CHECK(ods_point(&o, &x, &y, &z) == 1);
    CHECK_NEAR(z, 10, 1e-6);
    orr_error err = {0};
    CHECK(orr_stereo_ods_setup(&o, &p, ORR_EYE_LEFT, 1, 91, &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "zenith fade");
    orr_projection persp = PLANNED(.kind = ORR_PROJ_PERSPECTIVE, .width = 10, .height = 10, .fov_deg = 60);
    CHECK(orr_stereo_ods_setup(&o, &persp, ORR_EYE_LEFT, 1, 0, &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "sky projection");
}

/* ---- anaglyphs ---- */

static void compose1(orr_anaglyph_kind k, const float l[3], const float r[3], float out[3])
{
    orr_anaglyph_compose(k, l, r, 1, out);
}

static void test_anaglyph_channels(void)
{
    const float white[3] = {1, 1, 1}, black[3] = {0, 0, 0}, green[3] = {0, 1, 0};
    float o[3];
    /* Light in the left eye only: red only (grey, colour) ... */
    compose1(ORR_ANAGLYPH_GREY, white, black, o);
    CHECK(o[0] == 1 && o[1] == 0 && o[2] == 0);
    compose1(ORR_ANAGLYPH_COLOUR, white, black, o);
    CHECK(o[0] == 1 && o[1] == 0 && o[2] == 0);
    /* ... and in the right eye only: cyan only. */
    compose1(ORR_ANAGLYPH_GREY, black, white, o);
    CHECK(o[0] == 0 && o[1] == 1 && o[2] == 1);
    compose1(ORR_ANAGLYPH_COLOUR, black, white, o);
    CHECK(o[0] == 0 && o[1] == 1 && o[2] == 1);
    /* Grey takes Rec. 709 luminance; colour keeps the left eye's red only. */
    compose1(ORR_ANAGLYPH_GREY, green, black, o);
    CHECK_NEAR(o[0], 0.7152, 1e-6);
    compose1(ORR_ANAGLYPH_COLOUR, green, green, o);
    CHECK(o[0] == 0 && o[1] == 1 && o[2] == 0);
    /* Dubois: a white left eye gives red clipped to 1 (row sums 1.05,
     * -0.148, -0.115), a white right eye cyan (-0.05, 1.147, 1.115). */
    compose1(ORR_ANAGLYPH_DUBOIS, white, black, o);
    CHECK(o[0] == 1 && o[1] == 0 && o[2] == 0);
    compose1(ORR_ANAGLYPH_DUBOIS, black, white, o);
    CHECK(o[0] == 0 && o[1] == 1 && o[2] == 1);
}

static void test_dubois_matrices(void)
{
    /* The row sums of the published matrices (E. Dubois's red-cyan
     * least-squares matrices): a mid-grey eye shows them unclipped. */
    const double left_sums[3] = {1.050, -0.148, -0.115}, right_sums[3] = {-0.050, 1.147, 1.115};
    for (int c = 0; c < 3; c++) {
        double ls = 0, rs = 0;
        for (int k = 0; k < 3; k++) {
            ls += orr_dubois_red_cyan_left[c][k];
            rs += orr_dubois_red_cyan_right[c][k];
        }
        CHECK_NEAR(ls, left_sums[c], 1e-6);
        CHECK_NEAR(rs, right_sums[c], 1e-6);
    }
    /* So a scene the same in both eyes keeps its grey: 0.4 in, 0.4 out. */
    const float grey[3] = {0.4f, 0.4f, 0.4f};
    float o[3];
    compose1(ORR_ANAGLYPH_DUBOIS, grey, grey, o);
    for (int c = 0; c < 3; c++)
        CHECK_NEAR(o[c], 0.4, 0.001);
    /* Pure red in the left eye: the first column, clipped at 0. */
    const float red[3] = {0.5f, 0, 0}, black[3] = {0, 0, 0};
    compose1(ORR_ANAGLYPH_DUBOIS, red, black, o);
    CHECK_NEAR(o[0], 0.5 * 0.437, 1e-6);
    CHECK(o[1] == 0 && o[2] == 0);
    /* The output may be one of the inputs. */
    float l[3] = {1, 1, 1};
    orr_anaglyph_compose(ORR_ANAGLYPH_COLOUR, l, black, 1, l);
    CHECK(l[0] == 1 && l[1] == 0 && l[2] == 0);
}

/* ---- a pair's picture ---- */

static void test_pair_picture_layouts(void)
{
    /* 2 x 1 eyes: left pixels 0.1, 0.2, right 0.7, 0.8 (all channels). */
    float left[6] = {0.1f, 0.1f, 0.1f, 0.2f, 0.2f, 0.2f}, right[6] = {0.7f, 0.7f, 0.7f, 0.8f, 0.8f, 0.8f};
    float out[12];
    int w, h;
    orr_stereo_picture(ORR_STEREO_SIDE_BY_SIDE, ORR_ANAGLYPH_DUBOIS, left, right, 2, 1, 0, out, &w, &h);
    CHECK(w == 4 && h == 1);
    CHECK(out[0] == 0.1f && out[3] == 0.2f && out[6] == 0.7f && out[9] == 0.8f);
    orr_stereo_picture(ORR_STEREO_OVER_UNDER, ORR_ANAGLYPH_DUBOIS, left, right, 1, 2, 0, out, &w, &h);
    CHECK(w == 1 && h == 4);
    CHECK(out[0] == 0.1f && out[3] == 0.2f && out[6] == 0.7f && out[9] == 0.8f);
    /* Anaglyph of sRGB values: decoded, composed, encoded again. Colour
     * mode keeps the left's red and the right's green and blue exactly. */
    orr_stereo_picture(ORR_STEREO_ANAGLYPH, ORR_ANAGLYPH_COLOUR, left, right, 2, 1, 0, out, &w, &h);
    CHECK(w == 2 && h == 1);
    CHECK_NEAR(out[0], 0.1, 1e-5);
    CHECK_NEAR(out[1], 0.7, 1e-5);
    CHECK_NEAR(out[5], 0.8, 1e-5);
    /* Grey mode mixes in linear light: sRGB 0.5 grey is linear 0.214. */
    float g[3] = {0.5f, 0.5f, 0.5f}, k[3] = {0, 0, 0};
    orr_stereo_picture(ORR_STEREO_ANAGLYPH, ORR_ANAGLYPH_DUBOIS, g, k, 1, 1, 1, out, &w, &h);
    CHECK_NEAR(out[0], 0.5 * 1.05, 1e-5); /* linear input stays linear */
}

/* ---- scene keys ---- */

static orr_scene g_scene;

#define PERSP "input: {model: {name: mw-m31}}\ncamera: {projection: perspective, position: [0, 0, 50], look_at: [0, 0, 0]}\n"
#define DOME "input: {model: {name: mw-m31}}\ncamera: {projection: dome}\n"

static orr_status load(const char *yaml, orr_error *err)
{
    orr_error_clear(err);
    orr_scene_free(&g_scene);
    return orr_scene_load_string(&g_scene, yaml, "scene.yaml", "/base", NULL, 0, err);
}

static void test_scene_keys(void)
{
    orr_error err;
    CHECK(load(PERSP, &err) == ORR_OK);
    CHECK(g_scene.stereo.mode == ORR_STEREO_NONE && g_scene.picture.anaglyph == ORR_ANAGLYPH_DUBOIS);
    CHECK(load(PERSP "stereo: {mode: side-by-side, eye_separation: 0.5}\n", &err) == ORR_OK);
    CHECK(g_scene.stereo.mode == ORR_STEREO_SIDE_BY_SIDE);
    /* auto: the distance to look_at, taken from wherever the camera is. */
    CHECK(g_scene.stereo.convergence == 0);
    CHECK_NEAR(orr_stereo_convergence(&g_scene.stereo, &g_scene.camera, g_scene.camera.position), 50, 1e-12);
    CHECK_NEAR(orr_stereo_convergence(&g_scene.stereo, &g_scene.camera, orr_v3(0, 30, 40)), 50, 1e-12);
    CHECK_NEAR(orr_stereo_convergence(&g_scene.stereo, &g_scene.camera, orr_v3(0, 0, 20)), 20, 1e-12);
    CHECK(load(PERSP "stereo: {mode: anaglyph, eye_separation: 1, convergence: 20, anaglyph: grey}\n", &err) ==
          ORR_OK);
    CHECK(g_scene.picture.anaglyph == ORR_ANAGLYPH_GREY && g_scene.stereo.convergence == 20 && g_scene.stereo.eye_separation == 1);
    CHECK(orr_stereo_convergence(&g_scene.stereo, &g_scene.camera, orr_v3(0, 0, 7)) == 20);
    CHECK(load(DOME "stereo: {mode: separate, eye_separation: 0.1, zenith_fade: 40}\n", &err) == ORR_OK);
    CHECK(g_scene.stereo.zenith_fade == 40);

    CHECK(load("input: {model: {name: mw-m31}}\nstereo: {mode: anaglyph, eye_separation: 1}\n", &err) ==
          ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "stereo.mode");
    CHECK_CONTAINS(err.msg, "orthographic");
    CHECK(load(PERSP "stereo: {mode: anaglyph}\n", &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "stereo.eye_separation");
    CHECK(load(PERSP "stereo: {mode: sideways, eye_separation: 1}\n", &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "sideways");
    CHECK(load(PERSP "stereo: {mode: anaglyph, eye_separation: 0}\n", &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "stereo.eye_separation");
    CHECK(load(PERSP "stereo: {eye_separation: 1}\n", &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "stereo.mode is none");
    CHECK(load(PERSP "stereo: {mode: over-under, eye_separation: 1, anaglyph: grey}\n", &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "stereo.anaglyph");
    CHECK(load(PERSP "stereo: {mode: anaglyph, eye_separation: 1, zenith_fade: 10}\n", &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "stereo.zenith_fade");
    CHECK(load(DOME "stereo: {mode: anaglyph, eye_separation: 1, convergence: 5}\n", &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "stereo.convergence");
    CHECK(load("input: {model: {name: mw-m31}}\ncamera: {projection: perspective, position: [0, 0, 50], "
               "direction: [0, 0, -1]}\nstereo: {mode: anaglyph, eye_separation: 1}\n",
               &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "stereo.convergence");
    CHECK(load(DOME "stereo: {mode: anaglyph, eye_separation: 1, zenith_fade: 95}\n", &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "stereo.zenith_fade");
}

int main(void)
{
    RUN(test_perspective_eye_offsets);
    RUN(test_perspective_parallax);
    RUN(test_perspective_eye_rejects_bad_input);
    RUN(test_ods_equirectangular_ahead);
    RUN(test_ods_mirrored_map);
    RUN(test_ods_dome_horizon_and_zenith);
    RUN(test_ods_skips_inside_eye_circle);
    RUN(test_ods_zenith_fade);
    RUN(test_anaglyph_channels);
    RUN(test_dubois_matrices);
    RUN(test_pair_picture_layouts);
    RUN(test_scene_keys);
    return check_summary();
}
