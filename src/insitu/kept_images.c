/* A frame's images kept in memory for the caller (kept_images.h). */
#include "insitu/kept_images.h"

#include <stdlib.h>
#include <string.h>

#include "core/numbers.h"

static void free_image(orr_kept_image *im)
{
    for (int j = 0; j < im->nplanes; j++)
        orr_plane_free(&im->planes[j]);
    free(im->rgb);
    free(im->header);
    memset(im, 0, sizeof *im);
}

void orr_kept_clear(orr_kept_images *k)
{
    for (int i = 0; i < k->n; i++)
        free_image(&k->image[i]);
    free(k->image);
    memset(k, 0, sizeof *k);
}

/* One card's value as FITS writes it; returns the characters written. */
static size_t card_value(const orr_card *c, char *out, size_t size)
{
    if (c->type == ORR_CARD_DOUBLE) { /* "8.0", not "8": a reader keeps it a real number */
        size_t n = (size_t)orr_snprintf(out, size, "%.17g", c->dbl);
        if (!strpbrk(out, ".eEin") && n + 2 < size)
            n += (size_t)snprintf(out + n, size - n, ".0");
        return n;
    }
    if (c->type == ORR_CARD_LONG)
        return (size_t)orr_snprintf(out, size, "%lld", c->lng);
    if (c->type == ORR_CARD_BOOL)
        return (size_t)orr_snprintf(out, size, "%s", c->lng ? "T" : "F");
    size_t n = 0; /* a string: quoted, a quote inside doubled, as FITS does */
    out[n++] = '\'';
    for (const char *s = c->str; *s && n + 3 < size; s++) {
        if (*s == '\'')
            out[n++] = '\'';
        out[n++] = *s;
    }
    out[n++] = '\'';
    out[n] = '\0';
    return n;
}

char *orr_kept_header_text(const orr_cards *cards, orr_error *err)
{
    /* A line is at most 8 + 3 + 2 * 68 + 2 + 1 characters (a string of quotes). */
    enum { LINE_MAX = 160 };
    char *text = orr_malloc((size_t)cards->n * LINE_MAX + 1, "FITS header text", err);
    if (!text)
        return NULL;
    size_t used = 0;
    text[0] = '\0';
    for (int i = 0; i < cards->n; i++) {
        const orr_card *c = &cards->cards[i];
        if (c->type == ORR_CARD_UNSET) /* (a frame's header has none: orr_cards_drop_unset) */
            continue;
        used += (size_t)snprintf(text + used, LINE_MAX, "%s = ", c->key);
        used += card_value(c, text + used, LINE_MAX - 12);
        text[used++] = '\n';
        text[used] = '\0';
    }
    return text;
}

static orr_status copy_planes(orr_kept_image *im, const orr_plane *planes, int nplanes, orr_error *err)
{
    size_t npix = (size_t)im->width * (size_t)im->height;
    for (int j = 0; j < nplanes; j++) {
        orr_status st = orr_plane_alloc(&im->planes[j], im->width, im->height, planes[j].name, planes[j].unit, err);
        if (st)
            return st;
        im->nplanes = j + 1;
        memcpy(im->planes[j].data, planes[j].data, npix * sizeof(float));
    }
    return ORR_OK;
}

orr_status orr_kept_add(void *user, int view, const orr_plane *planes, int nplanes, const float *rgb,
                        const orr_cards *cards, orr_error *err)
{
    orr_kept_images *k = user;
    if (view != k->n || nplanes < 1 || nplanes > 3)
        return orr_fail(err, ORR_ERR_INTERNAL, "kept image %d of %d planes out of order", view, nplanes);
    if (k->n == k->capacity) {
        int cap = k->capacity ? 2 * k->capacity : 4;
        orr_kept_image *grown = realloc(k->image, (size_t)cap * sizeof *grown);
        if (!grown)
            return orr_fail(err, ORR_ERR_NOMEM, "out of memory keeping the images");
        k->image = grown;
        k->capacity = cap;
    }
    orr_kept_image *im = &k->image[k->n];
    memset(im, 0, sizeof *im);
    im->width = planes[0].width;
    im->height = planes[0].height;
    k->n++; /* counted at once, so that orr_kept_clear frees what a failure leaves */
    size_t nrgb = (size_t)im->width * (size_t)im->height * 3;
    orr_status st = copy_planes(im, planes, nplanes, err);
    if (!st && rgb && !(im->rgb = orr_malloc(nrgb * sizeof(float), "kept picture", err)))
        st = ORR_ERR_NOMEM;
    if (!st && rgb)
        memcpy(im->rgb, rgb, nrgb * sizeof(float));
    if (!st && !(im->header = orr_kept_header_text(cards, err)))
        st = ORR_ERR_NOMEM;
    return st;
}
