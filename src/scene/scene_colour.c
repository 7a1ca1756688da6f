#include "scene/scene_colour.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/owned.h"
#include "scene/scene_bind.h"
#include "scene/scene_value.h"

static orr_status get_name(const scene_at *at, const yt_node *n, char *out, size_t size)
{
    char buf[96];
    if (n->kind != YT_SCALAR || yt_is_null(n) || !n->text[0] || strlen(n->text) >= size)
        return scene_fail_at(at->err, at->origin, at->line, "%s: expected a name of 1 to %zu characters, got %s",
                             at->path, size - 1, yt_describe(n, buf, sizeof buf));
    snprintf(out, size, "%s", n->text);
    return ORR_OK;
}

static orr_status unknown(const scene_at *at, const yt_entry *e, const char *known)
{
    return scene_fail_at(at->err, at->origin, e->line ? e->line : at->line, "%s: unknown key '%s' (known: %s)",
                         at->path, e->key, known);
}

static orr_status want_mapping(const scene_at *at, const yt_node *n, const char *keys)
{
    char buf[96];
    if (n->kind == YT_MAPPING)
        return ORR_OK;
    return scene_fail_at(at->err, at->origin, at->line, "%s: expected a mapping of %s, got %s", at->path, keys,
                         yt_describe(n, buf, sizeof buf));
}

/* ---- select ---- */

static orr_status bind_types(const scene_at *at, const yt_node *n, uint32_t *mask)
{
    char buf[96];
    if (n->kind != YT_SEQUENCE || n->n == 0)
        return scene_fail_at(at->err, at->origin, at->line, "%s: expected a list of particle types 0 to 5, got %s",
                             at->path, yt_describe(n, buf, sizeof buf));
    *mask = 0;
    for (size_t i = 0; i < n->n; i++) {
        double t;
        orr_status st = scene_get_number(at, n->items[i], &t);
        if (st)
            return st;
        if (t != floor(t) || t < 0 || t > 5)
            return scene_fail_at(at->err, at->origin, at->line, "%s: particle types are 0 to 5, got %g", at->path, t);
        *mask |= 1u << (int)t;
    }
    return ORR_OK;
}

static orr_status bind_field_range(const scene_at *at, const yt_node *n, orr_pop_select *sel)
{
    orr_status st = want_mapping(at, n, "name, min, max");
    sel->field_min = -INFINITY;
    sel->field_max = INFINITY;
    for (size_t i = 0; !st && i < n->n; i++) {
        const yt_entry *e = &n->entries[i];
        scene_at c = scene_child_at(at, e);
        if (strcmp(e->key, "name") == 0)
            st = get_name(&c, e->value, sel->range_field, sizeof sel->range_field);
        else if (strcmp(e->key, "min") == 0)
            st = scene_get_number(&c, e->value, &sel->field_min);
        else if (strcmp(e->key, "max") == 0)
            st = scene_get_number(&c, e->value, &sel->field_max);
        else
            st = unknown(at, e, "name min max");
    }
    return st;
}

static orr_status bind_random(const scene_at *at, const yt_node *n, orr_pop_select *sel)
{
    orr_status st = want_mapping(at, n, "p, or field, law, v0, dv");
    sel->random = 1;
    sel->prob = ORR_PROB_CONSTANT;
    for (size_t i = 0; !st && i < n->n; i++) {
        const yt_entry *e = &n->entries[i];
        scene_at c = scene_child_at(at, e);
        if (strcmp(e->key, "p") == 0) {
            st = scene_get_number(&c, e->value, &sel->p);
        } else if (strcmp(e->key, "field") == 0) {
            st = get_name(&c, e->value, sel->prob_field, sizeof sel->prob_field);
        } else if (strcmp(e->key, "law") == 0) {
            char word[32] = "";
            st = get_name(&c, e->value, word, sizeof word);
            if (!st && (!orr_prob_kind_from_name(word, &sel->prob) || sel->prob == ORR_PROB_CONSTANT))
                st = scene_fail_at(at->err, c.origin, c.line, "%s: expected one of: exp logistic, got '%s'", c.path,
                                   word);
        } else if (strcmp(e->key, "v0") == 0) {
            st = scene_get_number(&c, e->value, &sel->v0);
        } else if (strcmp(e->key, "dv") == 0) {
            st = scene_get_number(&c, e->value, &sel->dv);
        } else {
            st = unknown(at, e, "p field law v0 dv");
        }
    }
    if (!st && sel->prob_field[0] && sel->prob == ORR_PROB_CONSTANT)
        st = scene_fail_at(at->err, at->origin, at->line, "%s: a field's probability needs law: exp or logistic",
                           at->path);
    return st;
}

static orr_status bind_select(const scene_at *at, const yt_node *n, orr_pop_select *sel)
{
    orr_status st = want_mapping(at, n, "types, ids, field, random");
    for (size_t i = 0; !st && i < n->n; i++) {
        const yt_entry *e = &n->entries[i];
        scene_at c = scene_child_at(at, e);
        if (strcmp(e->key, "types") == 0) {
            st = bind_types(&c, e->value, &sel->types);
        } else if (strcmp(e->key, "ids") == 0) {
            double r[2];
            st = scene_get_numbers(&c, e->value, r, 2, NULL);
            if (!st && !(r[0] >= 0 && r[1] >= r[0] && r[1] < 1.8e19))
                st = scene_fail_at(at->err, c.origin, c.line, "%s: expected [first, last] ids, first <= last", c.path);
            sel->has_id_range = 1;
            sel->id_min = (uint64_t)r[0];
            sel->id_max = (uint64_t)r[1];
        } else if (strcmp(e->key, "field") == 0) {
            st = bind_field_range(&c, e->value, sel);
        } else if (strcmp(e->key, "random") == 0) {
            st = bind_random(&c, e->value, sel);
        } else {
            st = unknown(at, e, "types ids field random");
        }
    }
    return st;
}

/* ---- colour and luminance ---- */

/* colour: {ssp: {field, clock, unit_yr, now, metallicity_field | metallicity, h, omega_m}} */
static orr_status bind_ssp(const scene_at *at, const yt_node *n, orr_pop_colour *col)
{
    static const char *const keys = "field clock unit_yr now metallicity_field metallicity h omega_m";
    orr_pop_ssp *ssp = &col->ssp;
    orr_status st = want_mapping(at, n, keys);
    col->kind = ORR_POPCOLOUR_SSP;
    for (size_t i = 0; !st && i < n->n; i++) {
        const yt_entry *e = &n->entries[i];
        scene_at c = scene_child_at(at, e);
        if (strcmp(e->key, "field") == 0) {
            st = get_name(&c, e->value, col->field, sizeof col->field);
        } else if (strcmp(e->key, "clock") == 0) {
            char word[32] = "", list[64];
            int v = ORR_SSP_CLOCK_AGE;
            st = get_name(&c, e->value, word, sizeof word);
            if (!st && !orr_named_value(orr_ssp_clock_names, word, &v))
                st = scene_fail_at(at->err, c.origin, c.line, "%s: expected one of: %s, got '%s'", c.path,
                                   orr_named_list(orr_ssp_clock_names, list, sizeof list), word);
            if (!st)
                ssp->clock = (orr_ssp_clock)v;
        } else if (strcmp(e->key, "unit_yr") == 0) {
            st = scene_get_number(&c, e->value, &ssp->unit_yr);
        } else if (strcmp(e->key, "now") == 0) {
            st = scene_get_number(&c, e->value, &ssp->now);
            ssp->has_now = 1;
        } else if (strcmp(e->key, "metallicity_field") == 0) {
            st = get_name(&c, e->value, ssp->metallicity_field, sizeof ssp->metallicity_field);
        } else if (strcmp(e->key, "metallicity") == 0) {
            st = scene_get_number(&c, e->value, &ssp->metallicity);
        } else if (strcmp(e->key, "h") == 0) {
            st = scene_get_number(&c, e->value, &ssp->h);
        } else if (strcmp(e->key, "omega_m") == 0) {
            st = scene_get_number(&c, e->value, &ssp->omega_m);
        } else {
            st = unknown(at, e, keys);
        }
    }
    if (!st && !col->field[0])
        st = scene_fail_at(at->err, at->origin, at->line, "%s: an ssp colour needs field: the age or formation field",
                           at->path);
    return st;
}

static orr_status bind_colour(const scene_at *at, const yt_node *n, orr_pop_colour *col)
{
    static const char *const keys = "temperature bv srgb linear_srgb xy temperature_field bv_field ssp";
    orr_status st = want_mapping(at, n, keys);
    if (!st && n->n != 1)
        return scene_fail_at(at->err, at->origin, at->line, "%s: give exactly one of: %s", at->path, keys);
    const yt_entry *e = st ? NULL : &n->entries[0];
    scene_at c = e ? scene_child_at(at, e) : *at;
    if (st) {
    } else if (strcmp(e->key, "temperature") == 0) {
        col->fixed.kind = ORR_COLOUR_TEMPERATURE;
        st = scene_get_number(&c, e->value, &col->fixed.v[0]);
    } else if (strcmp(e->key, "bv") == 0) {
        col->fixed.kind = ORR_COLOUR_BV;
        st = scene_get_number(&c, e->value, &col->fixed.v[0]);
    } else if (strcmp(e->key, "srgb") == 0 || strcmp(e->key, "linear_srgb") == 0) {
        col->fixed.kind = e->key[0] == 's' ? ORR_COLOUR_SRGB : ORR_COLOUR_LINEAR_SRGB;
        st = scene_get_numbers(&c, e->value, col->fixed.v, 3, NULL);
    } else if (strcmp(e->key, "xy") == 0) {
        col->fixed.kind = ORR_COLOUR_XY;
        st = scene_get_numbers(&c, e->value, col->fixed.v, 2, NULL);
    } else if (strcmp(e->key, "temperature_field") == 0 || strcmp(e->key, "bv_field") == 0) {
        col->kind = e->key[0] == 't' ? ORR_POPCOLOUR_TEMPERATURE : ORR_POPCOLOUR_BV;
        st = get_name(&c, e->value, col->field, sizeof col->field);
    } else if (strcmp(e->key, "ssp") == 0) {
        st = bind_ssp(&c, e->value, col);
    } else {
        st = unknown(at, e, keys);
    }
    return st;
}

static orr_status bind_luminance(const scene_at *at, const yt_node *n, orr_pop_luminance *lum)
{
    static const char *const keys = "constant, mass, ssp, field or magnitude_field (with scale)";
    orr_status st = want_mapping(at, n, keys);
    int rules = 0;
    for (size_t i = 0; !st && i < n->n; i++) {
        const yt_entry *e = &n->entries[i];
        scene_at c = scene_child_at(at, e);
        if (strcmp(e->key, "scale") == 0) {
            st = scene_get_number(&c, e->value, &lum->scale);
        } else if (strcmp(e->key, "constant") == 0 || strcmp(e->key, "mass") == 0 || strcmp(e->key, "ssp") == 0) {
            lum->kind = e->key[0] == 'c' ? ORR_POPLUM_CONSTANT : e->key[0] == 'm' ? ORR_POPLUM_MASS : ORR_POPLUM_SSP;
            st = scene_get_number(&c, e->value, &lum->scale);
            rules++;
        } else if (strcmp(e->key, "field") == 0 || strcmp(e->key, "magnitude_field") == 0) {
            lum->kind = e->key[0] == 'f' ? ORR_POPLUM_FIELD : ORR_POPLUM_MAGNITUDE;
            st = get_name(&c, e->value, lum->field, sizeof lum->field);
            rules++;
        } else {
            st = unknown(at, e, "constant mass ssp field magnitude_field scale");
        }
    }
    if (!st && rules != 1)
        st = scene_fail_at(at->err, at->origin, at->line, "%s: give exactly one of: %s", at->path, keys);
    return st;
}

/* ---- one population, and the list ---- */

static orr_status bind_population(const scene_at *at, const yt_node *n, orr_population *p)
{
    orr_status st = want_mapping(at, n, "name, select, colour, luminance");
    const yt_entry *name = st ? NULL : yt_find(n, "name");
    if (!st && !name)
        return scene_fail_at(at->err, at->origin, at->line, "%s: a population needs a name", at->path);
    char pname[ORR_POPULATION_NAME_MAX] = "";
    if (!st) {
        scene_at c = scene_child_at(at, name);
        st = get_name(&c, name->value, pname, sizeof pname);
    }
    if (!st)
        orr_population_defaults(p, pname);
    for (size_t i = 0; !st && i < n->n; i++) {
        const yt_entry *e = &n->entries[i];
        scene_at c = scene_child_at(at, e);
        if (strcmp(e->key, "name") == 0)
            continue;
        if (strcmp(e->key, "select") == 0)
            st = bind_select(&c, e->value, &p->select);
        else if (strcmp(e->key, "colour") == 0)
            st = bind_colour(&c, e->value, &p->colour);
        else if (strcmp(e->key, "luminance") == 0)
            st = bind_luminance(&c, e->value, &p->lum);
        else
            st = unknown(at, e, "name select colour luminance");
    }
    return st;
}

orr_status scene_bind_populations(orr_scene *s, const char *origin, int line, const char *path, const yt_node *n,
                                  orr_error *err)
{
    char buf[96];
    if (n->kind != YT_SEQUENCE || n->n == 0)
        return scene_fail_at(err, origin, line, "%s: expected a list of populations, got %s", path,
                             yt_describe(n, buf, sizeof buf));
    orr_population_set_init(&s->colour.populations, s->colour.populations.seed);
    for (size_t i = 0; i < n->n; i++) {
        scene_at at = {n->items[i]->origin, n->items[i]->line ? n->items[i]->line : line, "", err};
        snprintf(at.path, sizeof at.path, "%s[%zu]", path, i);
        orr_population p;
        orr_status st = bind_population(&at, n->items[i], &p);
        if (st)
            return st;
        if ((st = orr_population_add(&s->colour.populations, &p, err))) {
            char prefix[ORR_PATH_MAX + 32];
            scene_loc_prefix(at.origin, at.line, prefix, sizeof prefix);
            return orr_fail_prefix(err, "%s%s: ", prefix, at.path);
        }
    }
    s->colour.has_populations = 1;
    return ORR_OK;
}

orr_status scene_bind_tint(orr_scene *s, const char *origin, int line, const char *path, const yt_node *n,
                           orr_error *err)
{
    char buf[96];
    if (n->kind != YT_SEQUENCE || n->n < 1 || n->n > ORR_COLOUR_PATH_MAX)
        return scene_fail_at(err, origin, line, "%s: expected a list of 1 to %d temperatures (K), got %s", path,
                             ORR_COLOUR_PATH_MAX, yt_describe(n, buf, sizeof buf));
    scene_at at = {origin, line, "", err};
    snprintf(at.path, sizeof at.path, "%s", path);
    s->colour.tint.n = (int)n->n;
    for (size_t i = 0; i < n->n; i++) {
        orr_colour *c = &s->colour.tint.stop[i];
        memset(c, 0, sizeof *c);
        c->kind = ORR_COLOUR_TEMPERATURE;
        orr_status st = scene_get_number(&at, n->items[i], &c->v[0]);
        if (!st && !(c->v[0] > 0))
            st = scene_fail_at(err, origin, line, "%s: temperatures are > 0 K, got %g", path, c->v[0]);
        if (st)
            return st;
    }
    s->colour.has_tint = 1;
    return ORR_OK;
}

static orr_status bind_layer(const scene_at *at, const yt_node *n, struct orr_compose_layer *l)
{
    orr_status st = want_mapping(at, n, "file, colour, gain");
    l->gain = 1.0;
    for (size_t i = 0; !st && i < n->n; i++) {
        const yt_entry *e = &n->entries[i];
        scene_at c = scene_child_at(at, e);
        if (strcmp(e->key, "file") == 0) {
            char file[ORR_PATH_MAX];
            st = get_name(&c, e->value, file, sizeof file);
            if (!st)
                st = orr_owned_set(&l->file, file, at->err);
        } else if (strcmp(e->key, "gain") == 0) {
            st = scene_get_number(&c, e->value, &l->gain);
            if (!st && !(l->gain > 0))
                st = scene_fail_at(at->err, c.origin, c.line, "%s: expected a number > 0, got %g", c.path, l->gain);
        } else if (strcmp(e->key, "colour") == 0) {
            orr_pop_colour pc;
            memset(&pc, 0, sizeof pc);
            st = bind_colour(&c, e->value, &pc);
            if (!st && pc.kind != ORR_POPCOLOUR_FIXED)
                st = scene_fail_at(at->err, c.origin, c.line, "%s: a layer's colour is fixed (no *_field)", c.path);
            l->colour = pc.fixed;
            l->has_colour = 1;
        } else {
            st = unknown(at, e, "file colour gain");
        }
    }
    if (!st && !l->file)
        st = scene_fail_at(at->err, at->origin, at->line, "%s: a layer needs a file", at->path);
    return st;
}

orr_status scene_bind_layers(orr_scene *s, const char *origin, int line, const char *path, const yt_node *n,
                             orr_error *err)
{
    char buf[96];
    int max = (int)(sizeof s->compose.layers / sizeof s->compose.layers[0]);
    if (n->kind != YT_SEQUENCE || n->n < 1 || n->n > (size_t)max)
        return scene_fail_at(err, origin, line, "%s: expected a list of 1 to %d layers, got %s", path, max,
                             yt_describe(n, buf, sizeof buf));
    for (size_t i = 0; i < n->n; i++) {
        scene_at at = {n->items[i]->origin, n->items[i]->line ? n->items[i]->line : line, "", err};
        snprintf(at.path, sizeof at.path, "%.100s[%zu]", path, i);
        orr_owned_free(&s->compose.layers[i].file);
        memset(&s->compose.layers[i], 0, sizeof s->compose.layers[i]);
        orr_status st = bind_layer(&at, n->items[i], &s->compose.layers[i]);
        if (st)
            return st;
    }
    s->compose.nlayers = (int)n->n;
    return ORR_OK;
}
