/* The output keys whose values need more than their type's check: the
 * units written into FITS BUNIT/CUNIT (docs/output.md), which must be
 * strings astropy and other FITS readers parse, and the frame separator,
 * which goes into file names. */
#ifndef ORR_SCENE_OUTPUT_H
#define ORR_SCENE_OUTPUT_H

#include "core/error.h"
#include "scene/scene.h"
#include "scene/scene_bind.h"

/* The output keys' checks that span stages (output.alpha_mask with a
 * stereo pair, output.exr_population_layers with the colour populations);
 * the output's own are orr_output_prepare's (encode/output_settings.h). */
orr_status scene_check_output_keys(const orr_scene *s, const scene_marks *m, orr_error *err);

/* A HEALPix map's requirements: NGP deposits, no PSF, no stereo, only
 * FITS (output.png off unless asked for, which is an error); sets the
 * image size from camera.healpix_nside. The HEALPix keys are errors with
 * any other projection. */
orr_status scene_check_healpix(orr_scene *s, const scene_marks *m, orr_error *err);

/* The FITS unit of a particle's weight: output.bunit when given; for the
 * built-in model weighted by mass, its documented unit (10^10 solar masses,
 * docs/model.md); weighted by mass, the file's mass unit file_mass (a
 * source's info.mass_unit; NULL or "" unknown); else "" (unknown). */
const char *scene_weight_unit(const orr_scene *s, const char *file_mass);

/* The FITS unit of scene lengths: output.length_unit when given; kpc for the
 * built-in model; the file's file_length (NULL or "" unknown); else "". */
const char *scene_length_unit(const orr_scene *s, const char *file_length);

#endif
