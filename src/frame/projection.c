#include "frame/projection.h"
#include "core/simd.h"

#include <chealpix.h>
#include <math.h>
#include <string.h>

#include "core/fastmath.h"
#include "frame/project_point.h"

const orr_named orr_projection_names[] = {
    {"orthographic", ORR_PROJ_ORTHOGRAPHIC},   {"perspective", ORR_PROJ_PERSPECTIVE},
    {"hammer-aitoff", ORR_PROJ_HAMMER_AITOFF}, {"dome", ORR_PROJ_DOME},
    {"equirectangular", ORR_PROJ_EQUIRECTANGULAR}, {"healpix", ORR_PROJ_HEALPIX},
    {NULL, 0}};

const char *orr_projection_name(orr_projection_kind kind) { return orr_named_name(orr_projection_names, (int)kind); }

const orr_named orr_healpix_order_names[] = {{"ring", 0}, {"nested", 1}, {NULL, 0}};

void orr_projection_cards(const orr_projection *proj, orr_cards *h)
{
    const orr_projection_settings *p = &proj->settings;
    orr_cards_add_string(h, "PROJTYPE", orr_projection_name(p->kind), "projection");
    if (p->kind == ORR_PROJ_ORTHOGRAPHIC)
        orr_cards_add_double(h, "ORTHOWID", p->ortho_width, "image width in simulation length units");
    if (p->kind == ORR_PROJ_PERSPECTIVE) {
        orr_cards_add_double(h, "FOV", p->fov_deg, "[deg] field of view along the wider axis");
        orr_cards_add_double(h, "NEAR", p->near, "near plane distance");
    }
    if (p->kind == ORR_PROJ_DOME)
        orr_cards_add_double(h, "DOMEFOV", p->dome_fov_deg, "[deg] dome field of view");
}

void orr_projection_defaults(orr_projection_settings *p)
{
    memset(p, 0, sizeof *p);
    p->kind = ORR_PROJ_ORTHOGRAPHIC;
    p->width = 1024;
    p->height = 1024;
    p->ortho_width = 100;
    p->fov_deg = 60;
    p->near = 1e-3;
    p->dome_fov_deg = 180;
    p->healpix_nside = 64;
    p->lon_flip = 0;
}

/* The 12 nside^2 pixels, as a 4 nside x 3 nside image in pixel order: the
 * planes are then the map itself. Each covers 4 pi / npix sr. */
static void setup_healpix(orr_projection *p)
{
    int n = p->settings.healpix_nside;
    p->width = 4 * n;
    p->height = 3 * n;
    p->cx = 0.5 * p->width;
    p->cy = 0.5 * p->height;
    p->focal = sqrt(12.0 * n * n / (4.0 * ORR_PI));
    p->lon_sign = -1.0;
}

long orr_healpix_pixel(const orr_projection *p, double x, double y, double z)
{
    double v[3] = {z, -x, -y}; /* HEALPix's x toward phi = 0, its z the pole */
    long ipix = 0;
    if (p->settings.healpix_nested)
        vec2pix_nest(p->settings.healpix_nside, v, &ipix);
    else
        vec2pix_ring(p->settings.healpix_nside, v, &ipix);
    return ipix;
}

/* The parameters within their ranges, each message naming its key and
 * value: those of p's kind, or with every set all of them (a scene's, which
 * holds them all, used or not). The one place each range is checked. */
static orr_status check_ranges(const orr_projection_settings *p, int every, const orr_keys *keys,
                               orr_error *err)
{
    if (p->width <= 0 || p->height <= 0 || p->width > ORR_IMAGE_SIDE_MAX || p->height > ORR_IMAGE_SIDE_MAX)
        return orr_fail_key(keys, NULL, err, "image size %d x %d is out of range (1 to %d pixels a side)",
                            p->width, p->height, ORR_IMAGE_SIDE_MAX);
    int ortho = every || p->kind == ORR_PROJ_ORTHOGRAPHIC, persp = every || p->kind == ORR_PROJ_PERSPECTIVE;
    if (ortho && !(p->ortho_width > 0 && isfinite(p->ortho_width)))
        return orr_fail_key(keys, "camera.width", err, "camera.width: %g is out of range (must be > 0)",
                            p->ortho_width);
    if (persp && !(p->fov_deg > 0 && p->fov_deg < 180))
        return orr_fail_key(keys, "camera.fov", err, "camera.fov: %g is out of range (must be > 0 and < 180)",
                            p->fov_deg);
    if (persp && !(p->near >= 0 && isfinite(p->near)))
        return orr_fail_key(keys, "camera.near", err, "camera.near: %g is out of range (must be >= 0)", p->near);
    if (persp && !isfinite(p->shift_x)) /* a stereo eye's, which no key sets */
        return orr_fail(err, ORR_ERR_USAGE, "perspective principal-point shift %g is not a number", p->shift_x);
    if ((every || p->kind == ORR_PROJ_DOME) && !(p->dome_fov_deg >= 90 && p->dome_fov_deg <= 360))
        return orr_fail_key(keys, "camera.dome_fov", err, "camera.dome_fov: %g is out of range (90 to 360)",
                            p->dome_fov_deg);
    int n = p->healpix_nside; /* only HEALPix's: a scene's other projections ignore the key */
    if (p->kind == ORR_PROJ_HEALPIX && (n < 1 || n > ORR_HEALPIX_NSIDE_MAX || (n & (n - 1)) != 0))
        return orr_fail_key(keys, "camera.healpix_nside", err,
                            "camera.healpix_nside: must be a power of 2 (1, 2, 4, ..., %d), got %d",
                            ORR_HEALPIX_NSIDE_MAX, n);
    return ORR_OK;
}

orr_status orr_projection_prepare(const orr_projection_settings *p, const orr_keys *keys, orr_error *err)
{
    return check_ranges(p, 1, keys, err);
}

orr_status orr_projection_check(const orr_projection_settings *p, orr_error *err)
{
    return check_ranges(p, 0, NULL, err);
}

orr_status orr_projection_plan(orr_projection *p, const orr_projection_settings *settings, orr_error *err)
{
    *p = (orr_projection){.settings = *settings, .width = settings->width, .height = settings->height};
    const orr_projection_settings *s = &p->settings;
    p->cx = 0.5 * p->width;
    p->cy = 0.5 * p->height;
    int wider = p->width > p->height ? p->width : p->height;
    switch (s->kind) {
    case ORR_PROJ_ORTHOGRAPHIC:
        p->focal = p->width / s->ortho_width;
        return ORR_OK;
    case ORR_PROJ_PERSPECTIVE:
        p->focal = 0.5 * wider / tan(0.5 * s->fov_deg * ORR_PI / 180.0);
        p->cx += s->shift_x;
        return ORR_OK;
    case ORR_PROJ_HAMMER_AITOFF:
        /* The ellipse spans the image: semi-axes W/2 and H/2 (2:1 for true
         * equal areas). It covers 4 pi sr in pi W H / 4 pixels. */
        p->half_w = 0.5 * p->width;
        p->half_h = 0.5 * p->height;
        p->focal = 0.25 * sqrt((double)p->width * p->height);
        p->lon_sign = s->lon_flip ? 1.0 : -1.0;
        return ORR_OK;
    case ORR_PROJ_EQUIRECTANGULAR:
        p->focal = sqrt((double)p->width * p->height / (2.0 * ORR_PI * ORR_PI));
        p->lon_sign = s->lon_flip ? 1.0 : -1.0;
        return ORR_OK;
    case ORR_PROJ_HEALPIX:
        setup_healpix(p);
        return ORR_OK;
    case ORR_PROJ_DOME:
        p->half_w = p->half_h = 0.5 * (p->width < p->height ? p->width : p->height);
        p->theta_max = 0.5 * s->dome_fov_deg * ORR_PI / 180.0;
        p->focal = p->half_w / p->theta_max;
        return ORR_OK;
    }
    return orr_fail(err, ORR_ERR_INTERNAL, "unknown projection kind %d", (int)s->kind);
}

/* Hammer-Aitoff from a direction given by its components toward the map
 * centre (fwd), toward l = +90 (left) and toward b = +90 (up), without
 * trigonometry: with rho = cos b, cos b cos(l/2) = sqrt(rho (rho + fwd) / 2)
 * and cos b sin(l/2) = sign(left) sqrt(rho (rho - fwd) / 2), so
 * X = 2 sqrt2 cos b sin(l/2) / sqrt(1 + cos b cos(l/2)),
 * Y = sqrt2 sin b / sqrt(1 + cos b cos(l/2)), all over the radius r. In
 * pixels the sqrt2 factors cancel against the ellipse's semi-axes. */
static inline void hammer_aitoff(double fwd, double left, double up, double r, double half_w, double half_h,
                                 double lon_sign, double *u, double *v)
{
    double rho = sqrt(fwd * fwd + left * left);
    /* rho + fwd and rho - fwd multiply to left^2: compute the larger
     * directly and the smaller from it, which avoids cancellation near the
     * centre and the seam. */
    double big = rho + fabs(fwd), small = big > 0 ? left * left / big : 0.0;
    double cbc = sqrt(0.5 * rho * (fwd >= 0 ? big : small));
    double cbs = sqrt(0.5 * rho * (fwd >= 0 ? small : big));
    if (left < 0)
        cbs = -cbs;
    double k = 1.0 / sqrt(r * (r + cbc));
    *u = lon_sign * half_w * cbs * k;
    *v = -half_h * up * k;
}

int orr_project_point(const orr_projection *p, orr_vec3 c, double *px, double *py, double *scale)
{
    double r = orr_v3_norm(c);
    switch (p->settings.kind) {
    case ORR_PROJ_ORTHOGRAPHIC:
        *px = p->cx + p->focal * c.x;
        *py = p->cy + p->focal * c.y;
        *scale = p->focal;
        return 1;
    case ORR_PROJ_PERSPECTIVE:
        if (!(c.z > p->settings.near) || c.z <= 0)
            return 0;
        *scale = p->focal / c.z;
        *px = p->cx + *scale * c.x;
        *py = p->cy + *scale * c.y;
        return 1;
    case ORR_PROJ_HAMMER_AITOFF: {
        if (!(r > 0))
            return 0;
        double u, v;
        hammer_aitoff(c.z, -c.x, -c.y, r, p->half_w, p->half_h, p->lon_sign, &u, &v);
        *px = p->cx + u;
        *py = p->cy + v;
        *scale = p->focal / r;
        return 1;
    }
    case ORR_PROJ_EQUIRECTANGULAR: {
        if (!(r > 0))
            return 0;
        double l = atan2(-c.x, c.z), b = atan2(-c.y, sqrt(c.x * c.x + c.z * c.z));
        *px = p->cx + p->lon_sign * l * p->width / (2.0 * ORR_PI);
        *py = p->cy - b * p->height / ORR_PI;
        /* Pixel area per steradian grows as 1/cos b toward the poles. */
        *scale = p->focal / sqrt(fmax(cos(b), 1e-6)) / r;
        return 1;
    }
    case ORR_PROJ_HEALPIX: {
        if (!(r > 0))
            return 0;
        long k = orr_healpix_pixel(p, c.x, c.y, c.z);
        *px = (double)(k % p->width) + 0.5;
        *py = (double)(k / p->width) + 0.5;
        *scale = p->focal / r;
        return 1;
    }
    case ORR_PROJ_DOME: {
        double rho = sqrt(c.x * c.x + c.y * c.y);
        double theta = atan2(rho, c.z);
        if (!(r > 0) || theta > p->theta_max)
            return 0;
        /* Azimuthal equidistant: the radius on the master is proportional to
         * the angle from the zenith; the camera's x and y keep their
         * directions, so the front (+y) is at the bottom. */
        double k = rho > 0 ? p->focal * theta / rho : p->focal;
        *px = p->cx + k * c.x;
        *py = p->cy + k * c.y;
        double stretch = theta > 1e-9 ? theta / sin(theta) : 1.0; /* tangential over radial scale */
        *scale = p->focal * sqrt(fabs(stretch)) / r;
        return 1;
    }
    }
    return 0;
}

/* Each kind has its own loop (a constant kind for orr_project_point_f), so
 * the compiler can vectorise it. */
static ORR_ALWAYS_INLINE void project_loop(orr_projection_kind kind, const orr_projection *p, size_t n,
                                            const float *restrict x, const float *restrict y,
                                            const float *restrict z, float *restrict px, float *restrict py,
                                            float *restrict scale, uint8_t *restrict visible)
{
    const orr_proj_consts k = orr_proj_consts_of(p);
    for (size_t i = 0; i < n; i++) {
        orr_projected q = orr_project_point_f(kind, &k, x[i], y[i], z[i]);
        px[i] = q.px;
        py[i] = q.py;
        scale[i] = q.scale;
        visible[i] = (uint8_t)q.visible;
    }
}

#define PROJECT_LOOP(name, kind)                                                                            \
    ORR_VECTOR_CLONES                                                                                        \
    static void name(const orr_projection *p, size_t n, const float *restrict x, const float *restrict y,    \
                     const float *restrict z, float *restrict px, float *restrict py, float *restrict scale, \
                     uint8_t *restrict visible)                                                              \
    {                                                                                                        \
        project_loop(kind, p, n, x, y, z, px, py, scale, visible);                                           \
    }
PROJECT_LOOP(project_orthographic, ORR_PROJ_ORTHOGRAPHIC)
PROJECT_LOOP(project_perspective, ORR_PROJ_PERSPECTIVE)
PROJECT_LOOP(project_hammer_aitoff, ORR_PROJ_HAMMER_AITOFF)
PROJECT_LOOP(project_equirectangular, ORR_PROJ_EQUIRECTANGULAR)
PROJECT_LOOP(project_dome, ORR_PROJ_DOME)

/* HEALPix's pixel search (chealpix) does not vectorise: a plain loop. */
static void project_healpix(const orr_projection *p, size_t n, const float *x, const float *y, const float *z,
                            float *px, float *py, float *scale, uint8_t *visible)
{
    for (size_t i = 0; i < n; i++) {
        double sx, sy, s;
        visible[i] = (uint8_t)orr_project_point(p, orr_v3(x[i], y[i], z[i]), &sx, &sy, &s);
        px[i] = visible[i] ? (float)sx : 0.0f;
        py[i] = visible[i] ? (float)sy : 0.0f;
        scale[i] = visible[i] ? (float)s : 0.0f;
    }
}

int orr_projection_is_sky(const orr_projection *p)
{
    return orr_projection_traits_of(p->settings.kind).sky;
}

int orr_projection_pixel_in_map(const orr_projection *p, int i, int j)
{
    if (i < 0 || j < 0 || i >= p->width || j >= p->height)
        return 0;
    return orr_projection_point_in_map(p, i + 0.5, j + 0.5);
}

/* Bisection over columns lo .. hi of row j, whose pixels are on the map
 * and then off it (dir > 0: returns the last one on it, or lo - 1) or off
 * and then on (dir < 0: the first one on it, or hi + 1); by the test
 * itself, so the ends are its own answers. */
static int run_end(const orr_projection *p, int j, int lo, int hi, int dir)
{
    while (lo <= hi) {
        const int mid = lo + (hi - lo) / 2;
        const int on = orr_projection_pixel_in_map(p, mid, j);
        if (on == (dir > 0))
            lo = mid + 1;
        else
            hi = mid - 1;
    }
    return dir > 0 ? hi : lo;
}

int orr_projection_row_in_map(const orr_projection *p, int j, int *i0, int *i1)
{
    *i0 = *i1 = 0;
    if (j < 0 || j >= p->height || p->width <= 0)
        return 0;
    if (!orr_projection_traits_of(p->settings.kind).elliptic_map) {
        *i1 = p->width;
        return p->width;
    }
    /* The pixel centres nearest cx: if none of them is on the map, no
     * pixel of the row is (the test only grows away from cx). */
    const double c = floor(p->cx);
    int mid = c < 0 ? 0 : c > p->width - 1 ? p->width - 1 : (int)c;
    if (!orr_projection_pixel_in_map(p, mid, j) && !(mid > 0 && orr_projection_pixel_in_map(p, --mid, j)))
        return 0;
    *i0 = run_end(p, j, 0, mid, -1);
    *i1 = run_end(p, j, mid, p->width - 1, 1) + 1;
    return *i1 - *i0;
}

int orr_projection_point_in_map(const orr_projection *p, double x, double y)
{
    double u = x - p->cx, v = y - p->cy;
    switch (p->settings.kind) {
    case ORR_PROJ_HAMMER_AITOFF:
        u /= p->half_w;
        v /= p->half_h;
        return u * u + v * v <= 1.0;
    case ORR_PROJ_DOME:
        return u * u + v * v <= p->half_w * p->half_w;
    default:
        return 1;
    }
}

/* Half the width, in pixels, of the Hammer-Aitoff ellipse at the centre of row j. */
static double ellipse_half_width(const orr_projection *p, int j)
{
    double v = (j + 0.5 - p->cy) / p->half_h;
    return v * v < 1.0 ? p->half_w * sqrt(1.0 - v * v) : 0.0;
}

static int clamp_int(int v, int lo, int hi)
{
    return v < lo ? lo : v > hi ? hi : v;
}

static void fold_hammer_aitoff(const orr_projection *p, int *i, int *j)
{
    /* Past the top or bottom: the pole rows. Then, in the row, a pixel past
     * one edge of the ellipse belongs just inside the other edge (l = +-180
     * is one meridian), and anything still outside clamps to the row's ends. */
    *j = clamp_int(*j, 0, p->height - 1);
    double hw = ellipse_half_width(p, *j);
    while (hw < 0.5 && *j != (int)p->cy) { /* a row the ellipse misses: step toward the equator */
        *j += *j < (int)p->cy ? 1 : -1;
        hw = ellipse_half_width(p, *j);
    }
    double x = *i + 0.5 - p->cx;
    if (x < -hw)
        x += 2.0 * hw;
    else if (x > hw)
        x -= 2.0 * hw;
    int lo = (int)ceil(p->cx - hw - 0.5), hi = (int)floor(p->cx + hw - 0.5);
    if (lo > hi)
        lo = hi = (int)p->cx;
    *i = clamp_int((int)floor(p->cx + x), lo, hi);
}

static void fold_dome(const orr_projection *p, int *i, int *j)
{
    /* Pull the pixel centre radially back inside the circle, a little further
     * each time until it lands on a pixel whose centre is inside. */
    double u = *i + 0.5 - p->cx, v = *j + 0.5 - p->cy;
    double d = sqrt(u * u + v * v);
    for (double rmax = p->half_w - 0.5; rmax >= 0; rmax -= 0.5) {
        double k = d > rmax && d > 0 ? rmax / d : 1.0;
        *i = clamp_int((int)floor(p->cx + u * k), 0, p->width - 1);
        *j = clamp_int((int)floor(p->cy + v * k), 0, p->height - 1);
        if (orr_projection_pixel_in_map(p, *i, *j))
            return;
    }
    *i = (int)p->cx;
    *j = (int)p->cy;
}

/* The solid angle of the rectangle [x0, x1] x [y0, y1] of the image plane
 * at distance f from the eye: the corners' F(x, y) = atan(x y / (f r))
 * with r the distance to the corner (Oosterom & Strackee's formula for a
 * rectangle with a corner at the foot of the perpendicular). */
static double corner_angle(double x, double y, double f)
{
    return atan2(x * y, f * sqrt(x * x + y * y + f * f));
}

static double rectangle_solid_angle(double x0, double x1, double y0, double y1, double f)
{
    return corner_angle(x1, y1, f) - corner_angle(x0, y1, f) - corner_angle(x1, y0, f) + corner_angle(x0, y0, f);
}

double orr_pixel_measure(const orr_projection *p, int i, int j)
{
    switch (p->settings.kind) {
    case ORR_PROJ_ORTHOGRAPHIC:
        return 1.0 / (p->focal * p->focal);
    case ORR_PROJ_PERSPECTIVE: {
        double x0 = i - p->cx, y0 = j - p->cy;
        return rectangle_solid_angle(x0, x0 + 1.0, y0, y0 + 1.0, p->focal);
    }
    case ORR_PROJ_HAMMER_AITOFF:
        return 4.0 * ORR_PI / (ORR_PI * p->half_w * p->half_h);
    case ORR_PROJ_HEALPIX:
        return 4.0 * ORR_PI / ((double)p->width * p->height);
    case ORR_PROJ_EQUIRECTANGULAR: {
        double top = (p->cy - j) * ORR_PI / p->height, bottom = (p->cy - j - 1) * ORR_PI / p->height;
        return 2.0 * ORR_PI / p->width * (sin(top) - sin(bottom));
    }
    case ORR_PROJ_DOME: {
        double u = i + 0.5 - p->cx, v = j + 0.5 - p->cy;
        double theta = sqrt(u * u + v * v) / p->focal;
        double density = theta > 1e-4 ? sin(theta) / theta : 1.0 - theta * theta / 6.0;
        return density / (p->focal * p->focal);
    }
    }
    return 1.0;
}

/* The index mirroring k about centre c (2 c - 1 - k), or -1 when 2 c is
 * not a whole number: then no two pixels' offsets from c are surely the
 * same in floating point. Offsets k + 0.5 - c are exact for half-integer
 * c, so mirrored ones are equal and opposite. */
static long mirror_index(double c, int k)
{
    double twice = 2.0 * c;
    if (twice != floor(twice) || fabs(twice) > 1e9)
        return -1;
    return (long)twice - 1 - k;
}

void orr_pixel_measure_row(const orr_projection *p, int j, double *measure)
{
    orr_pixel_measure_span(p, j, 0, p->width, measure);
}

void orr_pixel_measure_span(const orr_projection *p, int j, int i0, int i1, double *measure)
{
    switch (p->settings.kind) {
    case ORR_PROJ_ORTHOGRAPHIC:
    case ORR_PROJ_HAMMER_AITOFF:
    case ORR_PROJ_HEALPIX:
    case ORR_PROJ_EQUIRECTANGULAR: { /* no dependence on i */
        double m = orr_pixel_measure(p, 0, j);
        for (int i = i0; i < i1; i++)
            measure[i] = m;
        return;
    }
    case ORR_PROJ_DOME:
        for (int i = i0; i < i1; i++) {
            long twin = mirror_index(p->cx, i);
            measure[i] = twin >= i0 && twin < i ? measure[twin] : orr_pixel_measure(p, i, j);
        }
        return;
    default:
        for (int i = i0; i < i1; i++)
            measure[i] = orr_pixel_measure(p, i, j);
        return;
    }
}

int orr_pixel_measure_twin_row(const orr_projection *p, int j)
{
    if (p->settings.kind != ORR_PROJ_DOME)
        return -1;
    long twin = mirror_index(p->cy, j);
    return twin >= 0 && twin < p->height && twin != j ? (int)twin : -1;
}

void orr_projection_fold(const orr_projection *p, int *i, int *j)
{
    switch (p->settings.kind) {
    case ORR_PROJ_HAMMER_AITOFF:
        fold_hammer_aitoff(p, i, j);
        return;
    case ORR_PROJ_DOME:
        fold_dome(p, i, j);
        return;
    case ORR_PROJ_EQUIRECTANGULAR:
        *i %= p->width;
        if (*i < 0)
            *i += p->width;
        *j = clamp_int(*j, 0, p->height - 1);
        return;
    default:
        return;
    }
}

void orr_project_batch(const orr_projection *p, size_t n, const float *x, const float *y,
                       const float *z, float *px, float *py, float *scale, uint8_t *visible)
{
    switch (p->settings.kind) {
    case ORR_PROJ_ORTHOGRAPHIC:
        project_orthographic(p, n, x, y, z, px, py, scale, visible);
        return;
    case ORR_PROJ_PERSPECTIVE:
        project_perspective(p, n, x, y, z, px, py, scale, visible);
        return;
    case ORR_PROJ_HAMMER_AITOFF:
        project_hammer_aitoff(p, n, x, y, z, px, py, scale, visible);
        return;
    case ORR_PROJ_EQUIRECTANGULAR:
        project_equirectangular(p, n, x, y, z, px, py, scale, visible);
        return;
    case ORR_PROJ_DOME:
        project_dome(p, n, x, y, z, px, py, scale, visible);
        return;
    case ORR_PROJ_HEALPIX:
        project_healpix(p, n, x, y, z, px, py, scale, visible);
        return;
    }
}

/* Inverse Hammer-Aitoff without trigonometry. With U, V the point's offsets
 * over the semi-axes, the textbook inverse has z^2 = 1 - X^2/16 - Y^2/4 =
 * 1 - (U^2 + V^2)/2, and z = D / sqrt2 where D^2 = 1 + cos b cos(l/2) is
 * the forward map's denominator, so cos b sin(l/2) = X z / 2,
 * cos b cos(l/2) = 2 z^2 - 1 and sin b = Y z; the double-angle formulas
 * then give cos b cos l and cos b sin l. */
static int unproject_hammer_aitoff(const orr_projection *p, double px, double py, orr_vec3 *dir)
{
    double u = (px - p->cx) / p->half_w, v = (py - p->cy) / p->half_h;
    double uv = u * u + v * v;
    if (!(uv <= 1.0))
        return 0;
    double z = sqrt(1.0 - 0.5 * uv);
    double X = p->lon_sign * 2.0 * sqrt(2.0) * u, Y = -sqrt(2.0) * v;
    double s = 0.5 * X * z, c = 2.0 * z * z - 1.0; /* cos b sin(l/2), cos b cos(l/2) */
    double cosb = sqrt(s * s + c * c);
    double fwd = cosb > 0 ? (c * c - s * s) / cosb : 0.0, left = cosb > 0 ? 2.0 * s * c / cosb : 0.0;
    *dir = orr_v3_normalize(orr_v3(-left, -Y * z, fwd));
    return 1;
}

static int unproject_dome(const orr_projection *p, double px, double py, orr_vec3 *dir)
{
    double u = px - p->cx, v = py - p->cy;
    double rho = sqrt(u * u + v * v);
    if (!(u * u + v * v <= p->half_w * p->half_w))
        return 0;
    double theta = rho / p->focal;
    double k = rho > 0 ? sin(theta) / rho : 0.0;
    *dir = orr_v3(k * u, k * v, cos(theta));
    return 1;
}

static int unproject_equirectangular(const orr_projection *p, double px, double py, orr_vec3 *dir)
{
    if (!(px >= 0 && px <= p->width && py >= 0 && py <= p->height))
        return 0;
    double l = p->lon_sign * (px - p->cx) * 2.0 * ORR_PI / p->width, b = (p->cy - py) * ORR_PI / p->height;
    *dir = orr_v3(-cos(b) * sin(l), -sin(b), cos(b) * cos(l));
    return 1;
}

/* The centre of the HEALPix pixel under (px, py). */
static int unproject_healpix(const orr_projection *p, double px, double py, orr_vec3 *dir)
{
    if (!(px >= 0 && px < p->width && py >= 0 && py < p->height))
        return 0;
    long k = (long)py * p->width + (long)px;
    double v[3];
    if (p->settings.healpix_nested)
        pix2vec_nest(p->settings.healpix_nside, k, v);
    else
        pix2vec_ring(p->settings.healpix_nside, k, v);
    *dir = orr_v3(-v[1], -v[2], v[0]);
    return 1;
}

int orr_unproject(const orr_projection *p, double px, double py, orr_vec3 *dir)
{
    switch (p->settings.kind) {
    case ORR_PROJ_ORTHOGRAPHIC:
        if (!isfinite(px) || !isfinite(py))
            return 0;
        *dir = orr_v3(0, 0, 1);
        return 1;
    case ORR_PROJ_PERSPECTIVE:
        if (!isfinite(px) || !isfinite(py))
            return 0;
        *dir = orr_v3_normalize(orr_v3((px - p->cx) / p->focal, (py - p->cy) / p->focal, 1.0));
        return 1;
    case ORR_PROJ_HAMMER_AITOFF:
        return unproject_hammer_aitoff(p, px, py, dir);
    case ORR_PROJ_DOME:
        return unproject_dome(p, px, py, dir);
    case ORR_PROJ_EQUIRECTANGULAR:
        return unproject_equirectangular(p, px, py, dir);
    case ORR_PROJ_HEALPIX:
        return unproject_healpix(p, px, py, dir);
    }
    return 0;
}
