#include "core/cards.h"

#include <ctype.h>
#include <stdio.h>
#include <string.h>
#include <strings.h>

/* Returns the next free card with its key set (upper case, as FITS wants),
 * or NULL for an unusable key or a full list. */
static orr_card *new_card(orr_cards *h, const char *key, orr_card_type type, const char *comment)
{
    size_t len = key ? strlen(key) : 0;
    if (len == 0 || len > 8 || h->n >= ORR_CARDS_MAX)
        return NULL;
    orr_card *c = &h->cards[h->n++];
    memset(c, 0, sizeof *c);
    for (size_t i = 0; i <= len; i++)
        c->key[i] = (char)toupper((unsigned char)key[i]);
    c->type = type;
    snprintf(c->comment, sizeof c->comment, "%s", comment ? comment : "");
    return c;
}

void orr_cards_add_string(orr_cards *h, const char *key, const char *value, const char *comment)
{
    orr_card *c = new_card(h, key, ORR_CARD_STRING, comment);
    if (c)
        snprintf(c->str, sizeof c->str, "%s", value ? value : "");
}

void orr_cards_add_double(orr_cards *h, const char *key, double value, const char *comment)
{
    orr_card *c = new_card(h, key, ORR_CARD_DOUBLE, comment);
    if (c)
        c->dbl = value;
}

void orr_cards_add_long(orr_cards *h, const char *key, long long value, const char *comment)
{
    orr_card *c = new_card(h, key, ORR_CARD_LONG, comment);
    if (c)
        c->lng = value;
}

void orr_cards_add_bool(orr_cards *h, const char *key, int value, const char *comment)
{
    orr_card *c = new_card(h, key, ORR_CARD_BOOL, comment);
    if (c)
        c->lng = value != 0;
}

void orr_cards_reserve(orr_cards *h, const char *key, const char *comment)
{
    new_card(h, key, ORR_CARD_UNSET, comment);
}

/* The first unset card of the key, or NULL. */
static orr_card *unset_card(orr_cards *h, const char *key)
{
    for (int i = 0; i < h->n; i++)
        if (h->cards[i].type == ORR_CARD_UNSET && strcasecmp(h->cards[i].key, key) == 0)
            return &h->cards[i];
    return NULL;
}

void orr_cards_set_string(orr_cards *h, const char *key, const char *value)
{
    orr_card *c = unset_card(h, key);
    if (c) {
        c->type = ORR_CARD_STRING;
        snprintf(c->str, sizeof c->str, "%s", value ? value : "");
    }
}

void orr_cards_set_double(orr_cards *h, const char *key, double value)
{
    orr_card *c = unset_card(h, key);
    if (c) {
        c->type = ORR_CARD_DOUBLE;
        c->dbl = value;
    }
}

void orr_cards_set_long(orr_cards *h, const char *key, long long value)
{
    orr_card *c = unset_card(h, key);
    if (c) {
        c->type = ORR_CARD_LONG;
        c->lng = value;
    }
}

void orr_cards_set_bool(orr_cards *h, const char *key, int value)
{
    orr_card *c = unset_card(h, key);
    if (c) {
        c->type = ORR_CARD_BOOL;
        c->lng = value != 0;
    }
}

void orr_cards_drop_unset(orr_cards *h)
{
    int kept = 0;
    for (int i = 0; i < h->n; i++)
        if (h->cards[i].type != ORR_CARD_UNSET)
            h->cards[kept++] = h->cards[i];
    h->n = kept;
}

void orr_cards_append(orr_cards *h, const orr_cards *from)
{
    for (int i = 0; i < from->n && h->n < ORR_CARDS_MAX; i++)
        h->cards[h->n++] = from->cards[i];
}
