#include "encode/output_settings.h"

#include <stdio.h>
#include <string.h>
#include <strings.h>

#include "core/owned.h"

const orr_named orr_png_transfer_names[] = {{"srgb", 0}, {"linear", 1}, {NULL, 0}};
const orr_named orr_png_bits_names[] = {{"8", 8}, {"16", 16}, {NULL, 0}};

void orr_output_settings_defaults(orr_output_settings *d)
{
    memset(d, 0, sizeof *d);
    d->write_fits = 1;
    d->write_png = 1;
    d->png_bits = 8;
    d->frame_digits = 4;
    snprintf(d->frame_separator, sizeof d->frame_separator, "_");
}

int orr_output_settings_strings(orr_output_settings *d, char **fields[])
{
    fields[0] = &d->dir;
    return ORR_OUTPUT_STRINGS;
}

void orr_output_settings_free(orr_output_settings *d)
{
    char **fields[ORR_OUTPUT_STRINGS];
    orr_owned_free_all(fields, orr_output_settings_strings(d, fields));
}

orr_status orr_output_settings_copy(orr_output_settings *dst, const orr_output_settings *src, orr_error *err)
{
    char **fields[ORR_OUTPUT_STRINGS];
    return orr_owned_copy(dst, src, sizeof *dst, fields, orr_output_settings_strings(dst, fields), err);
}

/* A weight unit is a product of FITS unit symbols with powers and a scale
 * ("solMass", "10**10 solMass", "erg s-1"): letters, digits, spaces and
 * "*", ".", "+", "-". A "/" is refused, since BUNIT appends " sr-1" and a
 * FITS "/" divides by everything after it. Returns the first bad character,
 * or 0. */
static char bad_unit_char(const char *u)
{
    for (const char *c = u; *c; c++)
        if (!strchr("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789 *.+-", *c))
            return *c;
    return 0;
}

/* A length unit is one symbol ("kpc", "Mpc", "m", "AU"), since BUNIT squares
 * it as "kpc-2". */
static int is_symbol(const char *u)
{
    if (!u[0])
        return 0;
    for (const char *c = u; *c; c++)
        if (!((*c >= 'a' && *c <= 'z') || (*c >= 'A' && *c <= 'Z')))
            return 0;
    return 1;
}

/* The separator stays in the file name, so it may not be a folder's '/' or
 * anything a shell or a playback system's file pattern would read. */
static orr_status check_frame_separator(const orr_output_settings *d, const orr_keys *keys, orr_error *err)
{
    if (strspn(d->frame_separator, "._-") != strlen(d->frame_separator))
        return orr_fail_key(keys, "output.frame_separator", err,
                            "output.frame_separator: '%s' may hold only '.', '_' and '-' (e.g. '.' for "
                            "NAME.00001.png)",
                            d->frame_separator);
    return ORR_OK;
}

/* output.image names a format by its extension, and not the EXR that
 * output.exr writes. */
static orr_status check_image(const orr_output_settings *d, const orr_keys *keys, orr_error *err)
{
    for (const char *c = d->image_ext; *c; c++)
        if (!((*c >= 'a' && *c <= 'z') || (*c >= 'A' && *c <= 'Z') || (*c >= '0' && *c <= '9')))
            return orr_fail_key(keys, "output.image", err,
                                "output.image: a file extension such as tif, jpg or exr (without the dot), got '%s'",
                                d->image_ext);
    /* Both would be DIR/NAME.exr: the picture, written second, would
     * replace the linear planes. */
    if (d->write_exr && strcasecmp(d->image_ext, "exr") == 0)
        return orr_fail_key(keys, "output.image", err,
                            "output.exr: true and output.image: %s both write NAME.exr, and the picture would "
                            "replace the linear planes: keep output.exr for the planes, or give output.image "
                            "another format (e.g. tif) for the picture",
                            d->image_ext);
    return ORR_OK;
}

orr_status orr_output_prepare(const orr_output_settings *d, const orr_keys *keys, orr_error *err)
{
    orr_status st = check_image(d, keys, err);
    if (!st)
        st = check_frame_separator(d, keys, err);
    if (st)
        return st;
    char bad = bad_unit_char(d->bunit);
    if (bad == '/')
        return orr_fail_key(keys, "output.bunit", err,
                            "output.bunit: '%s' divides with '/'; write a FITS unit with negative powers "
                            "instead, e.g. 'solMass yr-1'",
                            d->bunit);
    if (bad)
        return orr_fail_key(keys, "output.bunit", err,
                            "output.bunit: '%s' is not a FITS unit string (it has '%c'); e.g. 'solMass', "
                            "'10**10 solMass' or 'solLum'",
                            d->bunit, bad);
    if (d->length_unit[0] && !is_symbol(d->length_unit))
        return orr_fail_key(keys, "output.length_unit", err,
                            "output.length_unit: '%s' is not a single FITS unit symbol such as kpc, Mpc, pc or m",
                            d->length_unit);
    return ORR_OK;
}
