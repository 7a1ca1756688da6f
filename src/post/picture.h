/* The post stage's settings for how planes become a picture's values,
 * besides true colour (post/colour.h): a single-channel map's stretch and
 * colour map (the scene's output.stretch, .white, .white_percentile,
 * .softening, .colormap) and how a stereo pair becomes one anaglyph
 * (stereo.anaglyph). */
#ifndef ORR_POST_PICTURE_H
#define ORR_POST_PICTURE_H

#include "core/cards.h"
#include "post/anaglyph.h"
#include "post/colormap.h"
#include "post/stretch.h"

typedef struct orr_picture_settings {
    orr_stretch stretch;         /* output.stretch: linear | log | asinh (default log),
                                  * output.white: number > 0 or "auto" (default auto),
                                  * output.white_percentile (default 99.9),
                                  * output.softening: n of log/asinh (default 1000) */
    orr_colormap_kind colormap;  /* output.colormap: grey | magma | inferno (default magma) */
    orr_anaglyph_kind anaglyph;  /* stereo.anaglyph: grey | colour | dubois (default dubois) */
} orr_picture_settings;

/* Fills d with the defaults above. */
void orr_picture_settings_defaults(orr_picture_settings *d);

/* ANAGLYPH: how a stereo pair's picture was mixed (stereo.mode: anaglyph). */
void orr_picture_anaglyph_cards(const orr_picture_settings *d, orr_cards *h);

#endif
