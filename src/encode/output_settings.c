#include "encode/output_settings.h"

#include <stdio.h>
#include <string.h>

const orr_named orr_png_transfer_names[] = {{"srgb", 0}, {"linear", 1}, {NULL, 0}};
const orr_named orr_png_bits_names[] = {{"8", 8}, {"16", 16}, {NULL, 0}};

void orr_output_settings_defaults(orr_output_settings *d)
{
    memset(d, 0, sizeof *d);
    snprintf(d->dir, sizeof d->dir, ".");
    d->write_fits = 1;
    d->write_png = 1;
    d->png_bits = 8;
    d->frame_digits = 4;
    snprintf(d->frame_separator, sizeof d->frame_separator, "_");
}
