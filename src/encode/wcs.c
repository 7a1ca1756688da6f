#include "encode/wcs.h"

#include <stdio.h>

#define DEG (180.0 / ORR_PI)

/* The camera's axes in world coordinates: right (+x), down (+y), forward (+z). */
static void camera_axes(const orr_camera *cam, orr_vec3 *right, orr_vec3 *down, orr_vec3 *fwd)
{
    orr_mat3 m = orr_quat_to_mat3(cam->orientation);
    *right = orr_v3(m.m[0][0], m.m[1][0], m.m[2][0]);
    *down = orr_v3(m.m[0][1], m.m[1][1], m.m[2][1]);
    *fwd = orr_v3(m.m[0][2], m.m[1][2], m.m[2][2]);
}

/* The names of the longitude and latitude axes: GLON/GLAT only when an
 * observer frame defines galactic-like axes; otherwise the scene's own axes
 * (longitude about world z from world x), as a user-defined pair (paper II,
 * section 3.1: "xyLN"/"xyLT"), so no viewer takes them for galactic. */
static void axis_types(const orr_wcs_view *view, const char *code, char *c1, char *c2, size_t size)
{
    snprintf(c1, size, "%s-%s", view->observer_frame ? "GLON" : "WDLN", code);
    snprintf(c2, size, "%s-%s", view->observer_frame ? "GLAT" : "WDLT", code);
}

static void add_reference_pixel(orr_cards *h, const orr_projection *p)
{
    /* Image coordinate cx is FITS pixel cx + 0.5; rows are stored bottom-up. */
    orr_cards_add_double(h, "CRPIX1", p->cx + 0.5, "reference pixel: the map centre");
    orr_cards_add_double(h, "CRPIX2", p->height - p->cy + 0.5, NULL);
}

static void add_common(orr_cards *h, const orr_wcs_view *view, const char *code, double l0, double b0)
{
    char c1[16], c2[16];
    axis_types(view, code, c1, c2, sizeof c1);
    orr_cards_add_long(h, "WCSAXES", 2, "two world coordinate axes");
    orr_cards_add_string(h, "CTYPE1", c1,
                        view->observer_frame ? "longitude in the observer frame" : "longitude in the scene's axes");
    orr_cards_add_string(h, "CTYPE2", c2,
                        view->observer_frame ? "latitude in the observer frame" : "latitude in the scene's axes");
    orr_cards_add_string(h, "CUNIT1", "deg", NULL);
    orr_cards_add_string(h, "CUNIT2", "deg", NULL);
    add_reference_pixel(h, view->proj);
    orr_cards_add_double(h, "CRVAL1", l0, "[deg] longitude at the reference pixel");
    orr_cards_add_double(h, "CRVAL2", b0, "[deg] latitude at the reference pixel");
}

/* Hammer-Aitoff and equirectangular maps have a WCS without rotation only
 * when their centre is on the equator and up is north. */
static int centred_on_equator(const orr_camera *cam, const orr_sky_frame *f, double *l0)
{
    orr_vec3 right, down, fwd;
    camera_axes(cam, &right, &down, &fwd);
    if (fabs(orr_v3_dot(fwd, f->z)) > 1e-9 || orr_v3_dot(orr_v3_scale(down, -1), f->z) < 1 - 1e-9)
        return 0;
    double b0;
    orr_sky_lb(f, fwd, l0, &b0);
    return 1;
}

/* Intermediate world coordinates (degrees) of direction (l, b) in a
 * zenithal projection with reference point (l0, b0) and LONPOLE = 180:
 * x = R sin(phi), y = -R cos(phi) (paper II, eq. 12-15, native coordinates
 * from eq. 5), with R(theta) = 90 - theta for ARC and (180/pi) cot(theta)
 * for TAN. */
static void zenithal_intermediate(int gnomonic, double l, double b, double l0, double b0, double *x, double *y)
{
    double dl = (l - l0) / DEG, bb = b / DEG, bb0 = b0 / DEG;
    double phi = ORR_PI + atan2(-cos(bb) * sin(dl), sin(bb) * cos(bb0) - cos(bb) * sin(bb0) * cos(dl));
    double theta = asin(fmax(-1.0, fmin(1.0, sin(bb) * sin(bb0) + cos(bb) * cos(bb0) * cos(dl))));
    double r = gnomonic ? DEG / tan(theta) : 90.0 - theta * DEG;
    *x = r * sin(phi);
    *y = -r * cos(phi);
}

/* The dome master is azimuthal equidistant about its zenith, like -ARC about
 * its reference point, and a perspective frame is gnomonic about its view
 * direction, exactly -TAN: in both, pixel offsets and intermediate
 * coordinates differ by a fixed linear map (rotation, scale, mirror). It is
 * found from two directions a little off the centre, and written as the CD
 * matrix. */
static int add_zenithal(orr_cards *h, const orr_wcs_view *view, int gnomonic)
{
    const orr_projection *p = view->proj;
    const orr_sky_frame *f = view->frame;
    orr_vec3 right, down, fwd;
    camera_axes(view->camera, &right, &down, &fwd);
    double l0, b0;
    orr_sky_lb(f, fwd, &l0, &b0);
    orr_mat3 w2c = orr_camera_world_to_camera(view->camera);
    /* Inside a narrow perspective frame, and beyond its near distance
     * (a direction's length does not change where it projects). */
    double a = fmin(10.0, gnomonic ? p->settings.fov_deg / 4 : 10.0) / DEG, reach = 1.0 + 2.0 * p->settings.near;
    double P[2][2], X[2][2]; /* columns: the two test directions */
    orr_vec3 toward[2] = {right, down};
    for (int k = 0; k < 2; k++) {
        orr_vec3 d = orr_v3_add(orr_v3_scale(fwd, cos(a)), orr_v3_scale(toward[k], sin(a)));
        double px, py, s, l, b;
        if (!orr_project_point(p, orr_mat3_apply(w2c, orr_v3_scale(d, reach)), &px, &py, &s))
            return 0;
        P[0][k] = px - p->cx; /* FITS axis 1 runs with image x */
        P[1][k] = p->cy - py; /* FITS axis 2 runs against image y */
        orr_sky_lb(f, d, &l, &b);
        zenithal_intermediate(gnomonic, l, b, l0, b0, &X[0][k], &X[1][k]);
    }
    /* CD = X P^-1 maps pixel offsets to intermediate coordinates. */
    double det = P[0][0] * P[1][1] - P[0][1] * P[1][0];
    if (fabs(det) < 1e-12)
        return 0;
    double inv[2][2] = {{P[1][1] / det, -P[0][1] / det}, {-P[1][0] / det, P[0][0] / det}};
    add_common(h, view, gnomonic ? "TAN" : "ARC", l0, b0);
    orr_cards_add_double(h, "LONPOLE", 180.0, "[deg] native longitude of the frame's north pole");
    static const char *const names[2][2] = {{"CD1_1", "CD1_2"}, {"CD2_1", "CD2_2"}};
    for (int i = 0; i < 2; i++)
        for (int j = 0; j < 2; j++)
            orr_cards_add_double(h, names[i][j], X[i][0] * inv[0][j] + X[i][1] * inv[1][j], "[deg/pixel]");
    return 1;
}

/* An orthographic view is a plane: linear axes along the camera's right and
 * up, 0 at the view centre (the camera position), in scene lengths. */
static int add_linear(orr_cards *h, const orr_wcs_view *view)
{
    const orr_projection *p = view->proj;
    const char *unit = view->length_unit ? view->length_unit : "";
    orr_cards_add_long(h, "WCSAXES", 2, "two world coordinate axes");
    orr_cards_add_string(h, "CTYPE1", "CAMX", "offset along the camera's right");
    orr_cards_add_string(h, "CTYPE2", "CAMY", "offset along the camera's up");
    if (unit[0]) {
        orr_cards_add_string(h, "CUNIT1", unit, NULL);
        orr_cards_add_string(h, "CUNIT2", unit, NULL);
    }
    add_reference_pixel(h, p);
    orr_cards_add_double(h, "CRVAL1", 0.0, "the view centre");
    orr_cards_add_double(h, "CRVAL2", 0.0, NULL);
    orr_cards_add_double(h, "CDELT1", 1.0 / p->focal, "scene length per pixel");
    orr_cards_add_double(h, "CDELT2", 1.0 / p->focal, "scene length per pixel");
    return 1;
}

int orr_wcs_add_cards(orr_cards *h, const orr_wcs_view *view)
{
    const orr_projection *p = view->proj;
    double l0;
    switch (p->settings.kind) {
    case ORR_PROJ_HAMMER_AITOFF:
        if (!centred_on_equator(view->camera, view->frame, &l0))
            return 0;
        add_common(h, view, "AIT", l0, 0.0);
        /* x = (180/pi) X with X = 2 sqrt2 ... reaching 2 sqrt2 at the ellipse's
         * end, half_w pixels from the centre (likewise y: sqrt2 at half_h). */
        orr_cards_add_double(h, "CDELT1", p->lon_sign * DEG * 2 * sqrt(2.0) / p->half_w, "[deg/pixel]");
        orr_cards_add_double(h, "CDELT2", DEG * sqrt(2.0) / p->half_h, "[deg/pixel]");
        return 1;
    case ORR_PROJ_EQUIRECTANGULAR:
        if (!centred_on_equator(view->camera, view->frame, &l0))
            return 0;
        add_common(h, view, "CAR", l0, 0.0);
        orr_cards_add_double(h, "CDELT1", p->lon_sign * 360.0 / p->width, "[deg/pixel]");
        orr_cards_add_double(h, "CDELT2", 180.0 / p->height, "[deg/pixel]");
        return 1;
    case ORR_PROJ_DOME:
        return add_zenithal(h, view, 0);
    case ORR_PROJ_PERSPECTIVE:
        return add_zenithal(h, view, 1);
    case ORR_PROJ_ORTHOGRAPHIC:
        return add_linear(h, view);
    case ORR_PROJ_HEALPIX:
        return 0; /* a table of pixels: orr_wcs_healpix_coordsys */
    }
    return 0;
}

void orr_wcs_frame_cards(orr_cards *frame, const orr_cards *planned, const orr_wcs_view *view)
{
    *frame = *planned;
    orr_wcs_add_cards(frame, view);
}

const char *orr_wcs_healpix_coordsys(const orr_wcs_view *view)
{
    double l0;
    if (!view->observer_frame || !centred_on_equator(view->camera, view->frame, &l0))
        return NULL;
    return fabs(remainder(l0, 360.0)) < 1e-9 ? "G" : NULL;
}
