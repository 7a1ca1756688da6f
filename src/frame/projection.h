/* Projections map a point in the camera frame (x right, y down, z forward)
 * to continuous image coordinates plus the local scale in pixels per unit
 * length, or report it as not visible. Pixel (i, j) covers [i, i+1) x [j, j+1),
 * so its centre is at (i + 0.5, j + 0.5); row j = 0 is the top of the image.
 * The splatter knows only this interface. */
#ifndef ORR_FRAME_PROJECTION_H
#define ORR_FRAME_PROJECTION_H

#include <stddef.h>
#include <stdint.h>

#include "core/cards.h"
#include "core/error.h"
#include "core/keys.h"
#include "core/names.h"
#include "core/vecmath.h"

typedef enum {
    ORR_PROJ_ORTHOGRAPHIC,
    ORR_PROJ_PERSPECTIVE,
    ORR_PROJ_HAMMER_AITOFF,   /* full sky in a 2:1 ellipse, centre = view direction */
    ORR_PROJ_DOME,            /* azimuthal equidistant dome master, centre = dome zenith */
    ORR_PROJ_EQUIRECTANGULAR, /* full sky, longitude linear in x, 2:1 */
    ORR_PROJ_HEALPIX,         /* full sky in HEALPix's equal-area pixels (pixel k is image pixel
                               * (k mod 4 nside, k div 4 nside)); NGP points or SPH kernels
                               * (splat/healpix_kernel.h) */
} orr_projection_kind;

#define ORR_IMAGE_SIDE_MAX 65536
#define ORR_HEALPIX_NSIDE_MAX 4096

/* What a projection is asked to be: the keys a scene gives (camera.projection,
 * .width, .fov, .near, .dome_fov, .healpix_nside, .healpix_order, .lon_flip;
 * image.width, .height), or what a program fills. orr_projection_plan makes
 * the projection that renders with them. */
typedef struct orr_projection_settings {
    orr_projection_kind kind;
    int width, height;  /* image size in pixels (HEALPix's map is 4 nside x 3 nside whatever these say) */
    double ortho_width; /* orthographic: simulation units across the image width */
    double fov_deg;     /* perspective: field of view along the wider image axis */
    double near;        /* perspective: points with z <= near are not drawn */
    double shift_x;     /* perspective: horizontal principal-point shift in pixels (the image
                         * centre moves right by this much); 0 by default. Stereo's off-axis
                         * convergence shifts each eye's image this way (frame/stereo.h). */
    double dome_fov_deg;/* dome: full angle across the dome (180 for a hemisphere), 90 to 360 */
    int healpix_nside;  /* HEALPix: a power of 2, 1 to ORR_HEALPIX_NSIDE_MAX */
    int healpix_nested; /* HEALPix: NESTED pixel order (else RING) */
    int lon_flip;       /* sky maps: longitude grows to the right ("outside looking in");
                         * by default it grows to the left, as on the sky seen from inside */
} orr_projection_settings;

/* A projection ready to render: made only by orr_projection_plan, which
 * copies the settings in and derives the rest; read, never written, after. */
typedef struct orr_projection {
    orr_projection_settings settings; /* as planned */
    int width, height;  /* the image in pixels: the settings' (HEALPix: 4 nside x 3 nside) */
    double cx, cy;      /* image centre in pixel coordinates */
    double focal;       /* orthographic: pixels per unit; perspective: focal length in pixels;
                         * sky: pixels per radian (the isotropic equivalent at the centre) */
    double half_w, half_h; /* Hammer-Aitoff: the ellipse's semi-axes in pixels; dome: the radius */
    double theta_max;   /* dome: half the field of view, radians */
    double lon_sign;    /* sky: -1 when longitude grows to the left (the default), +1 when flipped */
} orr_projection;

/* The scene's defaults of the keys a projection holds: orthographic, 100
 * units across, or a 60 degree perspective, 1024 x 1024 pixels. */
void orr_projection_defaults(orr_projection_settings *p);

/* The words of camera.healpix_order (healpix_nested's 0 and 1). */
extern const orr_named orr_healpix_order_names[];

/* The HEALPix pixel (Gorski et al. 2005, ApJ 622, 759) of camera-frame
 * direction (x, y, z), not zero: the map's pole (theta = 0) is the camera's
 * up (-y) and longitude phi = 0 its view direction (+z), growing toward its
 * left (-x), like l on the other sky maps. */
long orr_healpix_pixel(const orr_projection *p, double x, double y, double z);

/* What a projection is, for the stages that treat projections differently
 * (splat/, render/): each a question they ask, answered here so that they
 * need not name the kinds. The formulas themselves stay in frame/
 * (projection.c, project_point.h). */
typedef struct orr_projection_traits {
    int sky;             /* covers directions all around (orr_projection_is_sky) */
    int parallel;        /* rays run parallel along +z, from no eye point (orthographic) */
    int rectilinear;     /* straight lines stay straight on the image (orthographic, perspective) */
    int off_axis_stereo; /* a stereo eye is the camera moved sideways, its principal point
                          * shifted (perspective); the others use omni-directional stereo */
    int elliptic_map;    /* the map is the ellipse of semi-axes half_w, half_h about (cx, cy)
                          * rather than the whole image (Hammer-Aitoff; the dome's circle) */
    int folds;           /* a deposit's pixels off the map fold back onto it (the sky maps but
                          * HEALPix, whose every pixel is on its map) */
    int wraps_longitude; /* the image's left and right edges are one meridian (equirectangular) */
    int rim;             /* the map's edge is the rim of the field of view, beyond which nothing
                          * is drawn (dome), not a seam where the sky goes on */
    int sheared_seam;    /* the seam is sheared differently on its two sides, so only a small
                          * kernel folds across it as one ellipse (Hammer-Aitoff) */
    int pixel_table;     /* the image is HEALPix's table of pixels: its own pixel search and
                          * deposit, FITS as a HEALPix table */
    int zenith_centred;  /* the image centre is the dome's zenith, aimed by the zenith and front
                          * directions rather than by the camera's centre and roll */
} orr_projection_traits;

static inline orr_projection_traits orr_projection_traits_of(orr_projection_kind kind)
{
    orr_projection_traits t = {0};
    switch (kind) {
    case ORR_PROJ_ORTHOGRAPHIC: t.parallel = t.rectilinear = 1; break;
    case ORR_PROJ_PERSPECTIVE: t.rectilinear = t.off_axis_stereo = 1; break;
    case ORR_PROJ_HAMMER_AITOFF: t.sky = t.elliptic_map = t.folds = t.sheared_seam = 1; break;
    case ORR_PROJ_DOME: t.sky = t.elliptic_map = t.folds = t.rim = t.zenith_centred = 1; break;
    case ORR_PROJ_EQUIRECTANGULAR: t.sky = t.folds = t.wraps_longitude = 1; break;
    case ORR_PROJ_HEALPIX: t.sky = t.pixel_table = 1; break;
    }
    return t;
}

/* Whether the projection covers directions all around (sky projections);
 * their deposits fold pixels outside the map back onto it instead of
 * counting them as lost. */
int orr_projection_is_sky(const orr_projection *p);

/* Whether pixel (i, j) of the image shows part of the map (inside the
 * Hammer-Aitoff ellipse, the dome's circle; every pixel of the others):
 * whether its centre is (orr_projection_point_in_map). */
int orr_projection_pixel_in_map(const orr_projection *p, int i, int j);

/* The pixels of row j on the map (orr_projection_pixel_in_map), [*i0, *i1);
 * returns their number (0, and both 0, for none). They are one run: the
 * outlines are convex, and the test grows with the distance from the
 * centre column on either side of it, rounding included. */
int orr_projection_row_in_map(const orr_projection *p, int j, int *i0, int *i1);

/* Whether the image point (x, y), in pixels from the image's top-left
 * corner, is inside the map's outline (the Hammer-Aitoff ellipse, the
 * dome's circle; everywhere for the others). */
int orr_projection_point_in_map(const orr_projection *p, double x, double y);

/* What pixel (i, j) covers: its solid angle in steradians for the sky
 * projections and perspective, its area in squared scene units for
 * orthographic. Exact for orthographic, perspective (the rectangle's solid
 * angle in closed form), Hammer-Aitoff (equal-area: 4 pi over the ellipse's
 * pi W H / 4 pixels) and equirectangular (a band of latitude); for the dome
 * the density sin(theta) / theta at the pixel's centre, which differs from
 * the pixel's integral in the second order of its angular size (under 1e-6
 * of it on a hemisphere 600 pixels across). A pixel is taken whole, also where the rim of the map cuts it
 * (its share of a deposit outside the map is folded back onto it). */
double orr_pixel_measure(const orr_projection *p, int i, int j);

/* orr_pixel_measure of every pixel of row j into measure[0, width), bit for
 * bit, evaluated once per distinct value: once for a row of the
 * projections whose measure depends on the row alone, once per mirror pair
 * of a dome's row (its pixels i and 2 cx - 1 - i are as far from the
 * centre, exactly, when 2 cx is a whole number). */
void orr_pixel_measure_row(const orr_projection *p, int j, double *measure);

/* The same for pixels [i0, i1) of row j only (measure[i] for i in the
 * range; the rest untouched), the same bits: a sky map's pixels off the
 * map need none. */
void orr_pixel_measure_span(const orr_projection *p, int j, int i0, int i1, double *measure);

/* The other row whose measures are row j's bit for bit (a dome's mirror
 * row 2 cy - 1 - j, when 2 cy is a whole number), or -1. */
int orr_pixel_measure_twin_row(const orr_projection *p, int j);

/* For a sky projection, moves pixel (i, j), possibly outside the image or
 * the map, to the pixel of the map where its share of a deposit belongs:
 * across the l = +-180 seam (Hammer-Aitoff, equirectangular), or to the
 * nearest pixel of the map (past the poles, the dome's rim). */
void orr_projection_fold(const orr_projection *p, int *i, int *j);

/* A scene's settings checked, every parameter whether its kind uses it or
 * not (camera.width, .fov, .near, .dome_fov: their ranges are the
 * projection's, not the key table's; .healpix_nside a power of 2 for
 * HEALPix), each message naming its key, value and, through keys, the file
 * and line where it was set (core/keys.h). The one check a scene's
 * projection gets: the plan takes it as checked. */
orr_status orr_projection_prepare(const orr_projection_settings *p, const orr_keys *keys, orr_error *err);

/* The same for settings a program fills itself: the parameters of their
 * kind, in the same words, with no place. */
orr_status orr_projection_check(const orr_projection_settings *p, orr_error *err);

/* The projection a view renders with, from settings that orr_projection_prepare
 * or orr_projection_check passed (or a planned projection's, changed within
 * their ranges): the settings copied into p and the rest derived (the image
 * size, the centre, the focal length, theta_max) in one place, when the
 * plan is made. The only way to make one; fails only on an unknown kind.
 * The sky projections take their direction from the camera frame:
 * Hammer-Aitoff and equirectangular put the view direction (+z) at the
 * centre, "up" (-y) at b = +90 and, by default, longitude growing to the
 * left (-x); the dome puts the view direction at its zenith (the image
 * centre) and the camera's down (+y) at the bottom of the master, the
 * dome's front. */
orr_status orr_projection_plan(orr_projection *p, const orr_projection_settings *settings, orr_error *err);

extern const orr_named orr_projection_names[];
/* The projection's cards: PROJTYPE and the parameters of its kind
 * (ORTHOWID; FOV and NEAR; DOMEFOV). */
void orr_projection_cards(const orr_projection *p, orr_cards *h);
const char *orr_projection_name(orr_projection_kind kind);

/* Projects one camera-frame point. Returns 1 and sets (px, py, scale) when the
 * point is visible; returns 0 when it is not (behind the near plane). Points
 * that project outside the image are still "visible": the deposit decides. */
int orr_project_point(const orr_projection *p, orr_vec3 cam, double *px, double *py, double *scale);

/* The same for n camera-frame points in SoA arrays, the form the hot loop
 * uses; visible[i] is 1 or 0, and px, py, scale are set only when visible.
 * The outputs must not overlap the inputs or each other (the loops are
 * vectorised on that promise). */
void orr_project_batch(const orr_projection *p, size_t n, const float *x, const float *y,
                       const float *z, float *px, float *py, float *scale, uint8_t *visible);

/* The inverse: the unit camera-frame direction (x right, y down, z forward)
 * of the continuous image point (px, py). Returns 1 and sets *dir when the
 * point is on the map: inside the Hammer-Aitoff ellipse, the dome's circle,
 * the equirectangular image; any point for perspective (the ray through
 * it); any point for orthographic, whose rays all run along +z. Returns 0
 * (dir untouched) otherwise. For a pixel centre it agrees with
 * orr_projection_pixel_in_map. */
int orr_unproject(const orr_projection *p, double px, double py, orr_vec3 *dir);

#endif
