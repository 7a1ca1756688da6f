#include "post/picture.h"

#include <string.h>

void orr_picture_anaglyph_cards(const orr_picture_settings *d, orr_cards *h)
{
    orr_cards_add_string(h, "ANAGLYPH", orr_anaglyph_name(d->anaglyph), "anaglyph of the PNG");
}

void orr_picture_settings_defaults(orr_picture_settings *d)
{
    memset(d, 0, sizeof *d);
    d->stretch = (orr_stretch){.kind = ORR_STRETCH_LOG, .white = 0, .white_percentile = 99.9, .n = 1000};
    d->colormap = ORR_CMAP_MAGMA;
    d->anaglyph = ORR_ANAGLYPH_DUBOIS;
}
