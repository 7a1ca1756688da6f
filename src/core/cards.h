/* A list of metadata cards {key, kind, value, comment}: how a stage
 * describes itself in the files it is written into (FITS header cards, and
 * through them the world coordinates, the PSF, the projection ...), as
 * plain data. Each stage adds its own cards (orr_projection_cards,
 * orr_view_psf_cards, ...); encode/ only writes the list (orr_write_fits).
 *
 * A list kept for a run of frames (a view's cards, made once by the
 * renderer's plan) reserves a card whose value each frame gives in its
 * place; each frame copies the list, sets those cards by key and drops the
 * ones it did not set, so the cards keep their order. */
#ifndef ORR_CORE_CARDS_H
#define ORR_CORE_CARDS_H

#define ORR_CARDS_MAX 160

typedef enum {
    ORR_CARD_STRING,
    ORR_CARD_DOUBLE,
    ORR_CARD_LONG,
    ORR_CARD_BOOL,
    ORR_CARD_UNSET, /* reserved, its value still to come (orr_cards_reserve); not written */
} orr_card_type;

typedef struct orr_card {
    char key[9];        /* at most 8 characters, upper case */
    orr_card_type type;
    char str[69];
    double dbl;
    long long lng;      /* also the BOOL value (0 or 1) */
    char comment[48];
} orr_card;

typedef struct orr_cards {
    int n;
    orr_card cards[ORR_CARDS_MAX];
    /* The text of the scene the planes were made from (YAML), which a FITS
     * file holds after them as its last HDU, EXTNAME 'SCENE': a
     * one-dimensional image of bytes (BITPIX 8), the text exactly; NULL or
     * "": none. Borrowed. */
    const char *scene;
} orr_cards;

/* Append a card; keys longer than 8 characters or a full list are
 * programming errors and are ignored with the list left unchanged. */
void orr_cards_add_string(orr_cards *h, const char *key, const char *value, const char *comment);
void orr_cards_add_double(orr_cards *h, const char *key, double value, const char *comment);
void orr_cards_add_long(orr_cards *h, const char *key, long long value, const char *comment);
void orr_cards_add_bool(orr_cards *h, const char *key, int value, const char *comment);

/* Reserves a card whose value each frame gives, in its place. */
void orr_cards_reserve(orr_cards *h, const char *key, const char *comment);
/* Gives the first unset card of that key its value (a key that is not
 * reserved is a programming error, ignored). */
void orr_cards_set_string(orr_cards *h, const char *key, const char *value);
void orr_cards_set_double(orr_cards *h, const char *key, double value);
void orr_cards_set_long(orr_cards *h, const char *key, long long value);
void orr_cards_set_bool(orr_cards *h, const char *key, int value);
/* Removes the cards still unset, keeping the others' order. */
void orr_cards_drop_unset(orr_cards *h);
/* Appends from's cards to h's (as many as fit). */
void orr_cards_append(orr_cards *h, const orr_cards *from);

#endif
