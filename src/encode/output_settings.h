/* The encode stage's settings: the scene's output.* keys that say which
 * files a view writes, where, and how they are named and encoded
 * (docs/scenes.md#output). How a plane's values become the picture's
 * (output.stretch, .white, .colormap...) is the post stage's
 * (post/picture.h). */
#ifndef ORR_ENCODE_OUTPUT_SETTINGS_H
#define ORR_ENCODE_OUTPUT_SETTINGS_H

#include "core/keys.h"
#include "core/limits.h"
#include "core/names.h"

typedef struct orr_output_settings {
    char *dir;                    /* output.dir, resolved against the current directory (default ".", which
                                   * the scene sets: these defaults allocate nothing); owned (core/owned.h) */
    char name[ORR_NAME_MAX];      /* output.name: base file name (default: the scene file's stem) */
    int write_fits;               /* output.fits (default true) */
    int write_png;                /* output.png (default true) */
    int write_exr;                /* output.exr: also NAME.exr, the linear planes as float OpenEXR
                                   * (default false) */
    int exr_half;                 /* output.exr_half: that file's samples as half floats (default false) */
    int exr_population_layers;    /* output.exr_population_layers: each colour population's X, Y, Z kept
                                   * as planes of their own and written as the layer NAME.R, NAME.G,
                                   * NAME.B, NAME.A (default false) */
    int fits_compress;            /* output.fits_compress: orr_fits_compression of NAME.fits (default none) */
    char image_ext[16];           /* output.image: also the picture as NAME.EXT in this format, e.g.
                                   * tif, jpg, exr (by OpenImageIO; default none) */
    int write_raw;                /* output.raw: also NAME.raw.fits, the planes before the PSF, for
                                   * `orrery compose` (default false) */
    int png_bits;                 /* output.png_bits: 8 | 16 (default 8) */
    int png_linear;               /* output.png_transfer: srgb (0, default) | linear (1): the transfer
                                   * curve of colour PNGs (colour maps are sRGB by definition) */
    char bunit[ORR_NAME_MAX];     /* output.bunit: the FITS unit of a particle's weight (default "": the
                                   * model's, else unknown, scene/scene_output.h); the planes' BUNIT is it
                                   * per steradian or per area (post/brightness.h) */
    char length_unit[ORR_NAME_MAX]; /* output.length_unit: the FITS unit of scene lengths (default "": kpc
                                     * for the model, else unknown) */
    long long frame_start;        /* output.frame_start: the number of a run's first frame (default 0) */
    int frame_digits;             /* output.frame_digits: at least this many digits (default 4) */
    char frame_separator[8];      /* output.frame_separator: between NAME and the number (default "_") */
    int alpha_mask;               /* output.alpha_mask: pictures as RGBA, transparent off the map */
} orr_output_settings;

/* The words of output.png_transfer (png_linear's 0 and 1) and of
 * output.png_bits. */
extern const orr_named orr_png_transfer_names[];
extern const orr_named orr_png_bits_names[];

/* Fills d, which holds no strings (zeroed or freed), with the defaults
 * above (the name and the folder are the scene's to give). */
void orr_output_settings_defaults(orr_output_settings *d);
/* d's owned strings (core/owned.h), at most ORR_OUTPUT_STRINGS, into fields; returns how many. */
#define ORR_OUTPUT_STRINGS 1
int orr_output_settings_strings(orr_output_settings *d, char **fields[]);
/* Frees d's strings. */
void orr_output_settings_free(orr_output_settings *d);
/* dst (its strings freed first) becomes a copy of src with strings of its own. */
orr_status orr_output_settings_copy(orr_output_settings *dst, const orr_output_settings *src, orr_error *err);

/* The output.* keys checked: output.image an extension, not the EXR of
 * output.exr; the frame separator, output.bunit and output.length_unit
 * usable in file names and FITS units. keys says which were given, and
 * where. (With the stereo pair and the colour populations:
 * scene/scene_output.c.) */
orr_status orr_output_prepare(const orr_output_settings *d, const orr_keys *keys, orr_error *err);

#endif
