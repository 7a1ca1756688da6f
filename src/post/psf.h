/* Point spread functions as convolution kernels (see docs/psf.md).
 *
 * Generated: the diffraction pattern of a telescope pupil (by default the
 * Hubble Space Telescope's, with the geometry Tiny Tim uses), |FT(pupil)|^2
 * summed over wavelengths within each colour band, each wavelength with its
 * own angular scale (lambda / aperture), so the spikes and rings spread in
 * colour as in real Hubble images.
 *
 * Loaded: a PSF image from a FITS file (a Tiny Tim model, an empirical star
 * stamp), binned or resampled to the output pixel scale with flux
 * conservation, recentred and normalised.
 *
 * Angles: counterclockwise from the image's +x axis (to the right) with +y
 * up the picture, as an astronomer reads a plot. */
#ifndef ORR_POST_PSF_H
#define ORR_POST_PSF_H

#include "core/error.h"
#include "core/keys.h"
#include "core/limits.h"
#include "core/names.h"
#include "post/convolve.h"

/* The PSF a view is drawn with (psf.kind). */
typedef enum {
    ORR_PSF_NONE,
    ORR_PSF_GAUSSIAN,
    ORR_PSF_HST,  /* generated from Hubble's pupil: docs/psf.md */
    ORR_PSF_FILE, /* a PSF image from FITS (e.g. Tiny Tim) */
} orr_psf_kind;

extern const orr_named orr_psf_kind_names[];

/* The post stage's psf.* and glow.* settings (docs/psf.md). Flat views
 * convolve the splatted plane with the PSF (FFT); sky maps, whose scale
 * varies across the image, draw each particle as a kernel of the PSF core's
 * angular size instead, and the brightest stars with the whole PSF
 * (post/sky_psf.h). */
typedef struct orr_psf_settings {
    orr_psf_kind kind;          /* psf.kind: none | gaussian | hst | file (default none) */
    int has_fwhm;               /* psf.fwhm was given */
    double fwhm;                /* psf.fwhm: Gaussian FWHM in pixels, flat views (default 3.6) */
    double fwhm_arcmin;         /* psf.fwhm_arcmin: FWHM in arcminutes on sky maps (0: auto, ORR_SKY_CORE_PIXELS
                                 * pixels at the map's centre), of the Gaussian or of the hst/file PSF's
                                 * core, which scales the whole PSF (default auto) */
    char *file;                 /* psf.file: a FITS PSF image (psf.kind: file); owned, NULL when unset
                                 * (core/owned.h) */
    int file_subsample;         /* psf.file_subsample: file pixels per detector pixel (default 1) */
    double arcsec_per_pixel;    /* psf.arcsec_per_pixel: the image's pixel scale for hst and file PSFs
                                 * (default 0.04, near Hubble ACS/WFC; 0 for a file: its own pixels) */
    double angle;               /* psf.angle: direction of the spikes, degrees (default 45) */
    double vane_width;          /* psf.vane_width: hst, the vanes' full width over the primary's radius
                                 * (default 0.022, Hubble's); wider vanes, brighter and shorter spikes */
    double spike_gain;          /* psf.spike_gain: hst, the spikes' light beyond the core times this, the PSF
                                 * renormalised (default 1: as diffraction makes them; an artist's choice) */
    int size;                   /* psf.size: odd kernel side in pixels (default 129) */
    int spike_stars;            /* psf.spike_stars: sky maps, hst/file: at most this many of the brightest
                                 * stars are drawn with the whole PSF, the others as its core (default 200) */
    double spike_min_flux;      /* psf.spike_min_flux: and none fainter than this fraction of the
                                 * brightest star (default 0.001) */
    double spike_flux;          /* psf.spike_flux: sky maps: and none of less flux at the camera than this,
                                 * in the key plane's units (default 0: no such bound) */
    int has_glow;
    double glow_threshold;      /* glow.threshold: sky maps: stars of less flux at the camera are drawn as
                                 * kernels as wide as the angle to their smoothing.neighbours-th nearest
                                 * star on the sky, brighter ones as the PSF's core (default: no glow) */
    double glow_max_arcmin;     /* glow.max_arcmin: ... and so are stars whose kernel would be wider than
                                 * this, where stars are sparse on the sky (default 60) */
} orr_psf_settings;

/* Fills d with the defaults above. */
void orr_psf_settings_defaults(orr_psf_settings *d);
/* d's owned strings (core/owned.h), at most ORR_PSF_STRINGS, into fields; returns how many. */
#define ORR_PSF_STRINGS 1
int orr_psf_settings_strings(orr_psf_settings *d, char **fields[]);

/* The psf.* and glow.* keys checked against each other and against the
 * map they are for (sky: a sky map); keys says which were given, and
 * where (core/keys.h). */
orr_status orr_psf_prepare(const orr_psf_settings *d, int sky, const orr_keys *keys, orr_error *err);

/* Whether a view draws its stars one by one, in pixels: a flat view with
 * psf.kind hst or file given psf.fwhm draws every star as the core of that
 * width and the brightest with the whole PSF (post/flat_psf.h), where
 * without psf.fwhm it convolves every star with the whole PSF. */
int orr_psf_flat_stars(const orr_psf_settings *d, int sky);

/* ---- the pupil ------------------------------------------------------------ */

#define ORR_PUPIL_MAX_PADS 8

/* Lengths other than the diameter are in units of the primary's radius. */
typedef struct orr_pupil {
    double diameter_m;   /* primary mirror diameter */
    double obscuration;  /* secondary mirror (shadow) radius */
    double spider_width; /* full width of each of the four vanes */
    double angle_deg;    /* direction of one vane; the others at +90, +180, +270 */
    int npads;           /* primary mirror pads (the mirror's mounting points) */
    /* Pad centres in the vanes' frame (x along the vane at angle_deg), so
     * they turn with the vanes, and pad radii. */
    double pad_x[ORR_PUPIL_MAX_PADS], pad_y[ORR_PUPIL_MAX_PADS], pad_radius[ORR_PUPIL_MAX_PADS];
} orr_pupil;

/* HST's Optical Telescope Assembly as in Tiny Tim's pupil tables: D = 2.4 m,
 * secondary radius 0.330, vane width 0.022 (26.4 mm), pads of radius 0.065
 * at (0.8921, 0), (-0.4615, 0.7555), (-0.4564, -0.7606); angle 45 degrees,
 * so the spikes form an X on the screen. */
void orr_pupil_hst(orr_pupil *p);

/* 1 where light passes at (x, y) (units of the primary radius, +y up),
 * 0 where the pupil is dark. */
int orr_pupil_open(const orr_pupil *p, double x, double y);

/* ---- generated PSFs ---------------------------------------------------- */

#define ORR_PSF_MAX_BANDS 8

/* A colour band: `samples` wavelengths at the midpoints of equal steps
 * between lambda_min and lambda_max (one sample: the middle), weighted
 * equally (a flat spectrum across the band). */
typedef struct orr_psf_band {
    char name[16];
    double lambda_min_nm, lambda_max_nm;
    int samples;
} orr_psf_band;

typedef struct orr_psf_params {
    orr_pupil pupil;
    double arcsec_per_pixel; /* output pixel scale */
    int size;                /* odd kernel side, pixels */
    int nbands;
    orr_psf_band bands[ORR_PSF_MAX_BANDS];
    /* Sampling (0 = automatic, see docs/psf.md): sub-samples per output
     * pixel side (odd), the fewest pupil samples across the diameter at the
     * longest wavelength, and anti-aliasing sub-samples per pupil pixel side
     * (used only on pixels an edge passes through). */
    int oversample;
    int min_pupil_samples;
    int pupil_supersample;
    /* Fraction of the kernel's radius over which it is rolled off to zero
     * (orr_image_kernel_taper), so the wings end softly; 0 = a square cut. */
    double taper;
} orr_psf_params;

/* HST pupil; bands B 400-500 nm, G 500-600, R 600-700, 5 wavelengths each;
 * 0.04 arcsec per pixel (1.2 pixels per lambda/D at 550 nm, near the
 * sampling of Hubble's ACS/WFC images); 129 x 129; taper 0.3. */
void orr_psf_hst_defaults(orr_psf_params *p);

/* lambda / D in arcseconds. */
double orr_lambda_over_d_arcsec(double lambda_nm, double diameter_m);

/* What generation chose, and the fraction of each band's light that fell
 * inside the square kernel before the taper (the rest, in the far wings,
 * is dropped by the normalisation to sum 1). */
typedef struct orr_psf_report {
    int fft_size;
    int oversample;
    double pupil_samples_min, pupil_samples_max; /* across the diameter */
    double captured[ORR_PSF_MAX_BANDS];
} orr_psf_report;

/* Fills kernels[0 .. nbands-1] (allocated here; free each with
 * orr_image_kernel_free), each normalised to sum 1, with arcsec_per_pixel
 * set. report may be NULL. */
orr_status orr_psf_generate(const orr_psf_params *p, orr_image_kernel *kernels, orr_psf_report *report,
                            orr_error *err);

/* ---- PSFs from FITS ------------------------------------------------------- */

typedef enum {
    ORR_PSF_CENTRE_PEAK,     /* the brightest pixel, refined by a parabola through its neighbours */
    ORR_PSF_CENTRE_CENTROID, /* flux-weighted centroid in a box around the brightest pixel */
} orr_psf_centre;

typedef struct orr_psf_fits_options {
    /* File pixels per detector pixel (Tiny Tim's "subsampling"); 0 or 1
     * for none. Without an output scale, the PSF is binned by this. */
    int subsample;
    /* Scale of the file's pixels; 0 = the PIXSCALE keyword (Tiny Tim). */
    double file_arcsec_per_pixel;
    /* Output scale; 0 = the file's detector pixels (file scale x subsample). */
    double arcsec_per_pixel;
    int size; /* odd output side; 0 = the largest odd size the image spans */
    orr_psf_centre centre;
    /* Subtract the median of the image's outermost pixels (a sky level)
     * before negative values are clipped to zero. */
    int subtract_background;
    double taper; /* as in orr_psf_params; 0 = none */
} orr_psf_fits_options;

typedef struct orr_psf_fits_info {
    int file_width, file_height;
    double file_arcsec_per_pixel; /* 0 when neither given nor in the header */
    double centre_x, centre_y;    /* in file pixels, pixel (i, j) covering [i, i+1) x [j, j+1), row 0 at the top */
    double ratio;                 /* output pixel side / file pixel side */
    double background;            /* subtracted level (0 unless asked) */
    double clipped;               /* sum of negative values set to zero */
    double captured;              /* fraction of the file's flux inside the kernel */
} orr_psf_fits_info;

/* Reads the first image HDU of path into out (allocated here), normalised to
 * sum 1 with the star in the centre pixel. opt NULL: defaults (subsample 1,
 * peak centring, no background subtraction). info may be NULL. */
orr_status orr_psf_load_fits(const char *path, const orr_psf_fits_options *opt, orr_image_kernel *out,
                             orr_psf_fits_info *info, orr_error *err);

/* Flux-conserving resampling: out (size x size) receives the integral of
 * img (w x h, row 0 at the top, pixels as unit squares, zero outside) over
 * square pixels `ratio` image pixels wide, the centre pixel centred on
 * (xc, yc) in the pixel convention above. With an integer ratio and a centre
 * on a pixel corner (even ratio) or pixel centre (odd ratio) this is plain
 * binning. */
orr_status orr_image_rebin(const float *img, int w, int h, double xc, double yc, double ratio, int size,
                           float *out, orr_error *err);

#endif
