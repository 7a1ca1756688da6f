/* The dust stage (docs/dust.md): the scene's dust: settings, and a frame's
 * dust, read from the particles once per frame, which dims (and with colour
 * reddens) every star's weights by the optical depth between the view's eye
 * (the observer, or the camera) and the star.
 *
 * The render driver keeps its part to hooks: orr_dust_frame_prepare after
 * the source is open, orr_dust_weights for each chunk and view, and
 * orr_dust_frame_free. */
#ifndef ORR_DUST_DUST_H
#define ORR_DUST_DUST_H

#include <stddef.h>

#include "core/error.h"
#include "core/limits.h"
#include "core/vecmath.h"
#include "dust/column.h"
#include "dust/curve.h"
#include "dust/redden.h"
#include "frame/projection.h"
#include "particles/chunk.h"
#include "source/source.h"
#include "core/names.h"
#include "core/plane.h"

typedef enum {
    ORR_DUST_CCM89 = 0, /* Cardelli, Clayton & Mathis (1989) with dust.r_v */
    ORR_DUST_CURVE_FILE, /* dust.curve_file */
    ORR_DUST_F99,        /* Fitzpatrick (1999) with dust.r_v */
} orr_dust_curve_kind;

extern const orr_named orr_dust_curve_names[];

/* The scene's dust.* keys (docs/scenes.md#dust). */
typedef struct orr_dust_settings {
    unsigned types;       /* dust.types: the particle types that are dust (bit t); 0: no dust (default) */
    double kappa_v;       /* dust.kappa_v: V-band opacity per unit dust mass, scene area / scene mass
                           * (required with dust.types) */
    double dust_to_gas;   /* dust.dust_to_gas: dust mass per unit particle mass (default 0.01) */
    char metallicity[ORR_FIELD_NAME_MAX]; /* dust.metallicity: a field Z; dust_to_gas is then scaled by
                                           * Z / dust.z_sun (default none) */
    double z_sun;         /* dust.z_sun: the metallicity dust_to_gas belongs to (default 0.0134, Asplund et
                           * al. 2009) */
    orr_dust_curve_kind curve; /* dust.curve: ccm89 (default) | f99 | file */
    double r_v;           /* dust.r_v: R_V of ccm89 and f99 (default 3.1) */
    char *curve_file;     /* dust.curve_file: two columns, nm and A_lambda/A_V (curve: file); owned,
                           * NULL when unset (core/owned.h) */
    int extinction_plane; /* dust.extinction_plane: also write A_V to infinity per pixel as a plane of
                           * the FITS / EXR files (default false) */
} orr_dust_settings;

/* Fills d, which holds no strings (zeroed or freed), with the defaults above. */
void orr_dust_settings_defaults(orr_dust_settings *d);
/* d's owned strings (core/owned.h), at most ORR_DUST_STRINGS, into fields; returns how many. */
#define ORR_DUST_STRINGS 1
int orr_dust_settings_strings(orr_dust_settings *d, char **fields[]);
/* Frees d's strings. */
void orr_dust_settings_free(orr_dust_settings *d);
/* dst (its strings freed first) becomes a copy of src with strings of its own. */
orr_status orr_dust_settings_copy(orr_dust_settings *dst, const orr_dust_settings *src, orr_error *err);
/* Cross-key checks; messages name the scene and the key. */
orr_status orr_dust_settings_check(const orr_dust_settings *d, const char *scene_path, unsigned drawn_types,
                                   orr_error *err);

/* Where a view looks from: a point (the observer, a perspective camera),
 * or with parallel set an orthographic camera's plane, through eye and
 * facing along the unit vector axis, each star seen from its foot on it. */
typedef struct orr_dust_eye {
    orr_vec3 eye;
    int parallel;
    orr_vec3 axis;
} orr_dust_eye;

/* A frame's dust. */
typedef struct orr_dust_frame {
    orr_dust_set set;
    orr_dust_redden red;
    int colour;            /* weights are X, Y, Z (reddened) rather than one (dimmed by e^-tau) */
    unsigned drawn_types;  /* input.types */
    float *out[ORR_PLANES_MAX]; /* the dimmed weights of the last chunk, out_planes of them */
    size_t out_cap;
    int out_planes;
    double *tau;           /* per particle of the last chunk */
    unsigned char *want;   /* per particle of the last chunk: drawn, so dimmed */
    size_t tau_cap;
    const orr_chunk *last_chunk; /* tau is of this chunk from last_eye (to share it across views) */
    uint64_t last_first;
    orr_dust_eye last_eye;
} orr_dust_frame;

/* What the frame needs beyond the settings. */
typedef struct orr_dust_context {
    const char *scene_path; /* for messages */
    orr_kernel_kind kernel; /* smoothing.kernel */
    int neighbours;         /* smoothing.neighbours: lengths for dust without its own */
    double h_scale;         /* the file's h to orrery's (support 2h) times smoothing.h_scale */
    int colour;             /* the render splats X, Y, Z */
    unsigned drawn_types;   /* input.types: only these are dimmed (the others weigh nothing) */
} orr_dust_context;

/* Reads the dust particles of src (rewound before and after), checks them
 * (a NaN or negative mass, smoothing length or metallicity is an
 * ORR_ERR_DATA error naming the particle), takes lengths from the
 * neighbours when the source has none, and builds the tree and tables. */
orr_status orr_dust_frame_prepare(orr_dust_frame *f, const orr_dust_settings *d, const orr_dust_context *ctx,
                                  orr_source *src, orr_error *err);
void orr_dust_frame_free(orr_dust_frame *f);


/* The weights w[0..nplanes) of chunk c dimmed by the dust between the eye
 * and each particle: w[k] is replaced by the frame's own array. */
orr_status orr_dust_weights(orr_dust_frame *f, const orr_dust_eye *eye, const orr_chunk *c, const float **w,
                            int nplanes, orr_error *err);

/* A_V to infinity from eye along the unit direction dir: the extinction
 * plane's pixels. */
double orr_dust_av_ray(const orr_dust_frame *f, orr_vec3 eye, orr_vec3 dir);

/* The extinction plane (dust.extinction_plane): A_V in magnitudes through
 * all of the dust behind each pixel centre, from the eye along the pixel's
 * ray (orthographic: from the pixel's point on the camera plane along the
 * view axis) to infinity; NaN off the map. The rays are independent: any
 * number of threads gives the same plane. out is allocated to the image's
 * size. */
orr_status orr_dust_av_plane(const orr_dust_frame *f, const orr_dust_eye *eye, const orr_projection *p,
                             const orr_mat3 *world_to_camera, orr_plane *out, orr_error *err);

#endif
