/* Camera paths: where the camera is and which way it looks in each frame of
 * an animation (docs/paths.md). A path is either a list of keyframes,
 * interpolated in the frame number, or a generator (orbit, line, inspiral,
 * rotate) that is a function of the run's parameter u = 0..1. An easing
 * curve reshapes either parameter so the camera can start and stop gently. */
#ifndef ORR_FRAME_PATH_H
#define ORR_FRAME_PATH_H

#include "core/error.h"
#include "core/names.h"
#include "core/vecmath.h"
#include "frame/camera.h"
#include "frame/timeline.h"

/* Keyframes a path holds. A scene is copied by value (one copy per view), so
 * the list is a fixed array; at 64 bytes a keyframe this is 16 KiB. */
#define ORR_PATH_KEYFRAMES_MAX 256

typedef enum {
    ORR_PATH_KEYFRAMES, /* interpolated keyframes, functions of the frame number */
    ORR_PATH_ORBIT,     /* a circle around a centre, looking at it */
    ORR_PATH_LINE,      /* a straight line at constant speed */
    ORR_PATH_INSPIRAL,  /* a spiral toward a target, looking at it */
    ORR_PATH_ROTATE,    /* a fixed position, the orientation turning about an axis */
} orr_path_kind;

/* Position interpolation between keyframes. Both are cubic Hermite
 * segments in the frame number; they differ in the tangents. */
typedef enum {
    ORR_PATH_CATMULL_ROM, /* m_i = (P[i+1] - P[i-1]) / (f[i+1] - f[i-1]) */
    ORR_PATH_HERMITE,     /* m_i = the mean of the two one-sided slopes (finite differences) */
} orr_path_interp;

/* Orientation interpolation between keyframes. */
typedef enum {
    ORR_ORIENT_SLERP, /* great-circle arcs: constant angular speed within a segment */
    ORR_ORIENT_SQUAD, /* Shoemake's spherical cubic: angular velocity continuous at keyframes */
} orr_path_orient;

typedef enum {
    ORR_EASE_NONE,   /* e(s) = s */
    ORR_EASE_IN,     /* e(s) = 1.5 s^2 - 0.5 s^3: starts at rest */
    ORR_EASE_OUT,    /* e(s) = 1 - ein(1 - s): ends at rest */
    ORR_EASE_IN_OUT, /* e(s) = 3 s^2 - 2 s^3 (smoothstep): starts and ends at rest */
} orr_ease;

typedef enum {
    ORR_RADIAL_EXPONENTIAL, /* r(u) = r0 (r1 / r0)^u: equal steps in log r, the same look at every scale */
    ORR_RADIAL_LINEAR,      /* r(u) = r0 + (r1 - r0) u */
} orr_radial_law;

typedef struct orr_keyframe {
    double frame;         /* may be fractional */
    orr_vec3 position;
    orr_quat orientation; /* unit; camera frame to world, as orr_camera */
} orr_keyframe;

/* How a keyframe is aimed, before it is turned into a quaternion. */
typedef enum { ORR_AIM_LOOK_AT, ORR_AIM_DIRECTION, ORR_AIM_QUATERNION } orr_key_aim;

typedef struct orr_keyframe_spec {
    double frame;
    orr_vec3 position;
    orr_key_aim aim;
    orr_vec3 look;   /* the look_at point or the direction */
    orr_quat quaternion;
    int has_up;
    orr_vec3 up;     /* default [0, 1, 0], as camera.up */
    double roll;     /* degrees */
} orr_keyframe_spec;

typedef struct orr_camera_path {
    orr_path_kind kind;
    orr_ease ease;

    /* keyframes */
    int nkeys;
    orr_keyframe keys[ORR_PATH_KEYFRAMES_MAX];
    orr_path_interp interpolation;
    orr_path_orient orientation;

    /* orbit and inspiral: the circle's centre (orbit) or the target
     * (inspiral) is `centre`; the plane's normal is `axis`; the angle is
     * start_angle + 360 turns u degrees, counter-clockwise seen from +axis,
     * measured from `ref`, a unit vector in the plane. */
    orr_vec3 centre, axis, ref;
    double radius;        /* orbit */
    double height;        /* orbit: the circle's offset from centre along axis (from a start point) */
    double r0, r1;        /* inspiral */
    orr_radial_law radial;
    double turns, start_angle;

    /* line */
    orr_vec3 from, to, up;
    int has_look_at;
    orr_vec3 look_at;

    /* rotate: a fixed camera whose orientation turns by angle * u degrees
     * about the world axis `axis` */
    orr_camera start;
    double angle;
} orr_camera_path;

/* Fills p with the defaults of a path of the given kind: axis [0, 0, 1],
 * one turn, start angle 0, catmull-rom, slerp, no easing, exponential
 * inspiral, up [0, 1, 0]. */
void orr_path_defaults(orr_camera_path *p, orr_path_kind kind);

/* The easing curve e(s) for s in [0, 1] (clamped outside). */
double orr_ease_apply(orr_ease ease, double s);

/* The in-plane reference direction for an orbit or inspiral: the world x
 * axis with its `axis` component removed (the world y axis when axis is
 * along x). Fails when axis is zero. */
orr_status orr_path_plane_ref(orr_vec3 axis, orr_vec3 *ref, orr_error *err);

/* Turns a keyframe spec into a keyframe (orientation from look_at,
 * direction (+ up, roll) or a quaternion, as the scene's camera keys). */
orr_status orr_keyframe_from_spec(const orr_keyframe_spec *spec, orr_keyframe *key, orr_error *err);

/* Checks a path's own consistency (at least 2 keyframes in increasing
 * frame order; a non-zero axis; radii > 0; ...). Messages name the
 * camera.path key. Also fills p->ref from p->axis for orbit and inspiral
 * when the caller has not set a start point. */
orr_status orr_path_check(orr_camera_path *p, orr_error *err);

/* The camera at a frame, the frame number possibly fractional (keyframes
 * use it) and u the run's parameter, 0..1 (the generators use it). */
orr_status orr_path_eval(const orr_camera_path *p, double frame, double u, orr_camera *cam, orr_error *err);

/* The camera of frame t: orr_path_eval(p, t->frame, t->u). This is what
 * the renderer calls per frame. */
orr_status orr_path_camera(const orr_camera_path *p, const orr_frame_time *t, orr_camera *cam, orr_error *err);

/* Reads keyframes from a CSV file: a header naming the columns, then one
 * row per keyframe (docs/paths.md). Columns: frame, x, y, z, and one of
 * look_x look_y look_z | dir_x dir_y dir_z | qw qx qy qz, optionally
 * up_x up_y up_z and roll. Blank lines and lines starting with '#' are
 * skipped. Errors name the file and line. */
orr_status orr_path_read_csv(const char *file, orr_keyframe *keys, int max, int *nkeys, orr_error *err);

/* The names of the path's settings: its kind, position interpolation,
 * orientation interpolation, easing and radial law. */
extern const orr_named orr_path_kind_names[];
extern const orr_named orr_path_interp_names[];
extern const orr_named orr_path_orient_names[];
extern const orr_named orr_ease_names[];
extern const orr_named orr_radial_law_names[];

const char *orr_path_kind_name(orr_path_kind kind);
int orr_path_kind_from_name(const char *name, orr_path_kind *kind);
int orr_ease_from_name(const char *name, orr_ease *ease);

#endif
