/* orrery's in-situ API: render a running simulation's particles every step,
 * without writing snapshots (docs/insitu.md). This is the one header a
 * simulation code includes; it is stable within a major version.
 *
 *   orrery_renderer *r;
 *   char msg[1024];
 *   if (orrery_open(&r, "futuresky.yaml", NULL, 0, msg, sizeof msg) != ORRERY_OK) { puts(msg); ... }
 *   for (step = 0; ...; step++) {
 *       ... advance the particles ...
 *       orr_particle_arrays p = {.struct_size = sizeof p, .n = n, .x = {pos, ORR_F64, 3 * sizeof(double)}, ...};
 *       if (orrery_render(r, &p, step) != ORRERY_OK) puts(orrery_error(r));
 *   }
 *   orrery_close(r);
 *
 * The library never prints and never exits: every function returns a status
 * (ORRERY_OK or one of the error codes) and orrery_error() says what went
 * wrong, naming the scene key, array or file. */
#ifndef ORRERY_H
#define ORRERY_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define ORRERY_API_VERSION 2 /* 2: orr_particle_arrays begins with struct_size */

/* Status codes (the library's orr_status values). */
#define ORRERY_OK 0
#define ORRERY_ERR_USAGE 2  /* a bad scene, key, value or argument */
#define ORRERY_ERR_IO 3     /* an output could not be written */
#define ORRERY_ERR_FORMAT 4 /* a file's contents are wrong */
#define ORRERY_ERR_DATA 5   /* the particles are unusable (NaN, a missing observer particle, ...) */
#define ORRERY_ERR_NOMEM 6
#define ORRERY_ERR_INTERNAL 7
#define ORRERY_ERR_CANCELLED 8 /* orrery_cancel stopped the render */

typedef enum { ORR_F32 = 1, ORR_F64 = 2 } orr_dtype;

/* One per-particle value: element i is at (char *)data + i * stride. */
typedef struct orr_array {
    const void *data;  /* NULL: absent */
    orr_dtype type;    /* ORR_F32 or ORR_F64 */
    size_t stride;     /* bytes from one particle to the next; 0 means packed. At least the
                        * element's size: a smaller one is refused, and so is one whose n
                        * elements would run past the end of memory (a negative stride cast
                        * to size_t). A broadcast array (one element repeated) is not packed:
                        * copy it out first. */
} orr_array;

#define ORR_ARRAYS_MAX_FIELDS 8

/* A process's particles, in the simulation's own memory: structure of
 * arrays (stride 0) or array of structures (stride = the structure's size),
 * float or double. Packed float arrays (and packed ids and types) are read
 * where they are, without a copy; other layouts are converted a chunk at a
 * time. They are only read. */
typedef struct orr_particle_arrays {
    /* sizeof(orr_particle_arrays) as the caller was compiled, so that a
     * later library with a larger structure knows which fields the caller
     * has; 0 means this (version 2) layout. Any other value is refused with
     * ORRERY_ERR_USAGE and a message giving both sizes. */
    size_t struct_size;
    size_t n;                  /* particles */
    orr_array x, y, z;         /* positions (required) */
    orr_array mass;            /* masses; absent: every particle has mass_value */
    double mass_value;
    const uint64_t *id;        /* ids (optional; absent: numbered from id_offset) */
    size_t id_stride;          /* bytes; 0 means packed */
    uint64_t id_offset;
    const uint8_t *type;       /* Gadget particle types 0..5 (optional; absent: 0) */
    size_t type_stride;        /* bytes; 0 means packed */
    orr_array h;               /* smoothing lengths, orrery's convention: kernel support 2h (optional) */
    orr_array vx, vy, vz;      /* velocities (optional): the fields "vx", "vy", "vz" */
    int nfields;               /* other named per-particle fields (e.g. "Vmag", "BV") */
    const char *field_names[ORR_ARRAYS_MAX_FIELDS];
    orr_array fields[ORR_ARRAYS_MAX_FIELDS];
    double time;               /* simulation time of these positions */
} orr_particle_arrays;

typedef struct orrery_renderer orrery_renderer;

/* Creates a renderer for a scene file (every view it has: dome masters,
 * panoramas, flat cameras, stereo), with "key=value" overrides as
 * `orrery render --set` takes them. The scene's input.* keys are ignored:
 * the particles come from orrery_render. The scene is planned here, once
 * for the run (projections, kernels, PSF, FFT plans), and every
 * orrery_render executes the plan. On failure *out is NULL and msg
 * (msg_size bytes, may be 0) holds the reason. */
int orrery_open(orrery_renderer **out, const char *scene_path, const char *const *overrides, int noverrides,
                char *msg, size_t msg_size);

/* The same from YAML text; relative paths in it resolve against base_dir.
 * Without output.name the outputs are named insitu_0000.png, ... */
int orrery_open_yaml(orrery_renderer **out, const char *yaml, const char *base_dir,
                     const char *const *overrides, int noverrides, char *msg, size_t msg_size);

/* Renders frame `frame` of every view from these particles and writes the
 * outputs (NAME_0000.png, ...). Camera paths are evaluated at the frame
 * (animation.frames is the run's length). The arrays are only read, and
 * need not outlive the call. */
int orrery_render(orrery_renderer *r, const orr_particle_arrays *p, long frame);

/* The last error's message ("" when none). */
const char *orrery_error(const orrery_renderer *r);

/* The files the last orrery_render wrote: count, and the i-th path. */
int orrery_output_count(const orrery_renderer *r);
const char *orrery_output(const orrery_renderer *r, int i);

/* Wall-clock seconds the last orrery_render took. */
double orrery_render_seconds(const orrery_renderer *r);

void orrery_close(orrery_renderer *r);

/* sizeof(orr_particle_arrays) in the library: bindings that mirror the
 * structure (the Python package's ctypes) check their copy against it. */
size_t orrery_particle_arrays_size(void);

/* ---- Images in memory (for Python and other callers that want arrays,
 * not files). After orrery_keep_images(r, 1), every orrery_render also
 * keeps a copy of each view's images until the next orrery_render or
 * orrery_close: the linear planes exactly as the FITS file holds them, the
 * graded picture the PNG shows, and the FITS cards. Image i is the i-th view
 * (a stereo view gives two: left eye, then right). The files are written as
 * the scene says (output.fits: false and output.png: false write none). */

/* Turns keeping on (keep != 0) or off; returns ORRERY_OK. */
int orrery_keep_images(orrery_renderer *r, int keep);

/* Images the last orrery_render kept (0 when keeping is off). */
int orrery_image_count(const orrery_renderer *r);

/* Image i's size in pixels and its number of planes (1: the weight; 3:
 * CIE X, Y, Z with colour). ORRERY_ERR_USAGE for no such image. */
int orrery_image_size(const orrery_renderer *r, int i, int *width, int *height, int *nplanes);

/* Plane j of image i: width * height floats, row-major, row 0 at the top
 * (the FITS file's rows are bottom-up, so row 0 here is its last row), and
 * its name (the FITS EXTNAME) and unit (BUNIT) when name/unit are not NULL.
 * NULL for no such plane. */
const float *orrery_image_plane(const orrery_renderer *r, int i, int j, const char **name, const char **unit);

/* Image i's graded picture: width * height * 3 sRGB-encoded values in
 * [0, 1], interleaved R, G, B, row 0 at the top. NULL for no such image. */
const float *orrery_image_rgb(const orrery_renderer *r, int i);

/* Image i's FITS cards as text, one card a line: "KEY = VALUE", VALUE a
 * quoted string ('' for a quote inside), T or F, an integer or a number
 * that reads back exactly. NULL for no such image. */
const char *orrery_image_header(const orrery_renderer *r, int i);

/* ---- Progress. fn(user, done, total) is called from the thread that
 * called orrery_render, between chunks of particles: done particles read
 * of total (-1 when unknown). NULL turns it off. Returns ORRERY_OK. */
typedef void (*orrery_progress_fn)(void *user, uint64_t done, int64_t total);
int orrery_set_progress(orrery_renderer *r, orrery_progress_fn fn, void *user);

/* Asks the render running in r to stop: from its progress callback, or
 * from another thread. The render stops before it reads its next chunk
 * (a request after the last chunk still stops it), writes no file, keeps
 * no image, and orrery_render returns ORRERY_ERR_CANCELLED; r renders the
 * next frame as usual. orrery_render clears the request when it begins, so
 * a request made while nothing renders is forgotten. Returns ORRERY_OK. */
int orrery_cancel(orrery_renderer *r);

/* ---- Particle files read with orrery's own readers (every format
 * `orrery render` reads: docs/input.md), one chunk at a time, for callers
 * that want the particles rather than an image (the Python package's
 * orrery.open). */
typedef struct orrery_reader orrery_reader;

/* Opens path (format NULL or "auto": detected from its first bytes) to be
 * read chunk_size particles at a time (0: 2^20). fields names the other
 * fields wanted (datasets, blocks, columns; nfields of them, at most 16);
 * NULL: every field the file has. ORRERY_OK, or an error code with the
 * reason in msg. */
int orrery_reader_open(orrery_reader **out, const char *path, const char *format, size_t chunk_size,
                       const char *const *fields, int nfields, char *msg, size_t msg_size);
const char *orrery_reader_format(const orrery_reader *rd);
/* Particles in the file, -1 when unknown before it is read (text). */
long long orrery_reader_count(const orrery_reader *rd);
/* The snapshot's time (0 when the file has none). */
double orrery_reader_time(const orrery_reader *rd);
/* Whether chunks carry "h" (smoothing lengths), "id", "type" from the file
 * (without, ids count from 0 and types are 0). */
int orrery_reader_has(const orrery_reader *rd, const char *what);
/* The radius where the file's kernel ends in units of its h (Gadget 1,
 * SWIFT about 1.8; orrery's own convention 2). */
double orrery_reader_h_support(const orrery_reader *rd);
/* The other fields every chunk has: count, and the i-th name. */
int orrery_reader_field_count(const orrery_reader *rd);
const char *orrery_reader_field_name(const orrery_reader *rd, int i);
/* Reads the next chunk: *n particles, 0 at the end. An error code (with
 * orrery_reader_error) for a file that cannot be read on; the same error
 * again at every later call. */
int orrery_reader_next(orrery_reader *rd, size_t *n);
/* The last chunk's floats of a field: "x", "y", "z", "mass", "h" or another
 * field's name; its ids and types. Valid until the next orrery_reader_next;
 * NULL for no such field. */
const float *orrery_reader_field(const orrery_reader *rd, const char *name);
const uint64_t *orrery_reader_ids(const orrery_reader *rd);
const uint8_t *orrery_reader_types(const orrery_reader *rd);
const char *orrery_reader_error(const orrery_reader *rd);
void orrery_reader_close(orrery_reader *rd);

#ifdef __cplusplus
}
#endif

#endif
