#include "source/settings.h"

#include <stdio.h>
#include <string.h>

const orr_named orr_nonfinite_names[] = {{"error", 0}, {"skip", 1}, {NULL, 0}};

void orr_input_cards(const orr_input_settings *d, orr_cards *h)
{
    orr_cards_add_string(h, "WEIGHT", d->weight, "particle field deposited");
}

void orr_input_settings_defaults(orr_input_settings *d)
{
    memset(d, 0, sizeof *d);
    snprintf(d->format, sizeof d->format, "auto");
    d->model.particles = 200000;
    d->model.seed = 1;
    d->model.separation = 780;
    d->model.galaxies = 0; /* ORR_MODEL_PAIR */
    d->model.disc_q = 1.5;
    d->model.w0 = 7;
    d->model.core_radius = 1;
    d->model.mass = 5e5;
    snprintf(d->weight, sizeof d->weight, "mass");
    d->type_mask = 0x3f;
    d->chunk_size = 1048576;
    d->skip_nonfinite = 0;
    d->sequence.first = 0;
    d->sequence.step = 1;
    d->sequence.interpolation = ORR_INTERP_AUTO;
    d->sequence.max_memory = 16;
}
