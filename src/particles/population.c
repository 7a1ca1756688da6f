#include "particles/population.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "core/digest.h"
#include "core/ssp.h"

/* ---- hashing ------------------------------------------------------------------ */

uint64_t orr_hash64(uint64_t x)
{
    /* SplitMix64: add the golden-ratio increment, then the Stafford "Mix13"
     * finaliser. Constants from Steele, Lea & Flood (OOPSLA 2014). */
    uint64_t z = x + 0x9E3779B97F4A7C15u;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9u;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBu;
    return z ^ (z >> 31);
}

/* The part of a draw that depends on the seed and salt only. */
static uint64_t draw_key(uint64_t seed, uint64_t salt) { return orr_hash64(seed ^ orr_hash64(salt)); }

static double keyed_uniform(uint64_t id, uint64_t key)
{
    /* Hashing the id on its own first spreads consecutive ids over all 64
     * bits before the key is mixed in, so ids 1, 2, 3 ... with any key give
     * unrelated draws. The top 53 bits make the double. */
    uint64_t h = orr_hash64(orr_hash64(id) ^ key);
    return (double)(h >> 11) * 0x1.0p-53;
}

double orr_id_uniform(uint64_t id, uint64_t seed, uint64_t salt)
{
    return keyed_uniform(id, draw_key(seed, salt));
}

uint64_t orr_name_salt(const char *name) { return orr_digest_text(ORR_DIGEST_START, name); }

/* ---- names --------------------------------------------------------------------- */

static const char *const prob_names[] = {
    [ORR_PROB_CONSTANT] = "constant", [ORR_PROB_EXP] = "exp", [ORR_PROB_LOGISTIC] = "logistic"};
#define PROB_COUNT ((int)(sizeof prob_names / sizeof prob_names[0]))

int orr_prob_kind_from_name(const char *name, orr_prob_kind *kind)
{
    for (int i = 0; name && i < PROB_COUNT; i++) {
        if (strcmp(name, prob_names[i]) == 0) {
            *kind = (orr_prob_kind)i;
            return 1;
        }
    }
    return 0;
}

const char *orr_prob_kind_name(orr_prob_kind kind)
{
    return (int)kind >= 0 && (int)kind < PROB_COUNT ? prob_names[kind] : "unknown";
}

const orr_named orr_ssp_clock_names[] = {{"age", ORR_SSP_CLOCK_AGE},
                                          {"time", ORR_SSP_CLOCK_TIME},
                                          {"scale_factor", ORR_SSP_CLOCK_SCALE_FACTOR},
                                          {NULL, 0}};

void orr_pop_ssp_defaults(orr_pop_ssp *ssp)
{
    memset(ssp, 0, sizeof *ssp);
    ssp->clock = ORR_SSP_CLOCK_AGE;
    ssp->unit_yr = 1;
    ssp->h = 0.674;
    ssp->omega_m = 0.315;
    ssp->metallicity = 0.0152;
}

/* ---- probability ------------------------------------------------------------------ */

static double clip01(double p)
{
    if (p > 1)
        return 1;
    return p > 0 ? p : 0; /* NaN gives 0 */
}

double orr_pop_probability(const orr_pop_select *sel, double v)
{
    switch (sel->prob) {
    case ORR_PROB_CONSTANT:
        return clip01(sel->p);
    case ORR_PROB_EXP:
        return clip01(exp(-(v - sel->v0) / sel->dv));
    case ORR_PROB_LOGISTIC:
        return clip01(1.0 / (1.0 + exp((v - sel->v0) / sel->dv)));
    }
    return 0;
}

/* ---- building a set ---------------------------------------------------------------- */

void orr_population_defaults(orr_population *p, const char *name)
{
    memset(p, 0, sizeof *p);
    if (name)
        snprintf(p->name, sizeof p->name, "%s", name);
    p->select.field_min = -INFINITY;
    p->select.field_max = INFINITY;
    p->colour.kind = ORR_POPCOLOUR_FIXED;
    p->colour.fixed.kind = ORR_COLOUR_SRGB;
    p->colour.fixed.v[0] = p->colour.fixed.v[1] = p->colour.fixed.v[2] = 1;
    orr_pop_ssp_defaults(&p->colour.ssp);
    p->lum.kind = ORR_POPLUM_CONSTANT;
    p->lum.scale = 1;
}

void orr_population_set_init(orr_population_set *s, uint64_t seed)
{
    memset(s, 0, sizeof *s);
    s->seed = seed;
}

int orr_population_find(const orr_population_set *s, const char *name)
{
    for (int i = 0; i < s->n; i++)
        if (strcmp(s->pop[i].name, name) == 0)
            return i;
    return -1;
}

/* A field name is set when it is a non-empty string within its array. */
static int name_set(const char *name, size_t size) { return name[0] && memchr(name, 0, size); }

#define NAME_SET(a) name_set((a), sizeof(a))

static orr_status check_select(const orr_pop_select *sel, orr_error *err)
{
    if (sel->has_id_range && sel->id_min > sel->id_max)
        return orr_fail(err, ORR_ERR_USAGE, "id range %llu..%llu is empty", (unsigned long long)sel->id_min,
                        (unsigned long long)sel->id_max);
    if (sel->range_field[0] && !NAME_SET(sel->range_field))
        return orr_fail(err, ORR_ERR_USAGE, "range field name too long");
    if (NAME_SET(sel->range_field) && !(sel->field_min <= sel->field_max))
        return orr_fail(err, ORR_ERR_USAGE, "range of '%s': [%g, %g] is empty", sel->range_field, sel->field_min,
                        sel->field_max);
    if (!sel->random)
        return ORR_OK;
    switch (sel->prob) {
    case ORR_PROB_CONSTANT:
        if (!(sel->p >= 0 && sel->p <= 1))
            return orr_fail(err, ORR_ERR_USAGE, "probability %g must be in [0, 1]", sel->p);
        return ORR_OK;
    case ORR_PROB_EXP:
    case ORR_PROB_LOGISTIC:
        if (!NAME_SET(sel->prob_field))
            return orr_fail(err, ORR_ERR_USAGE, "%s probability needs a field", orr_prob_kind_name(sel->prob));
        if (!isfinite(sel->v0) || !isfinite(sel->dv) || sel->dv == 0)
            return orr_fail(err, ORR_ERR_USAGE, "%s probability of '%s': v0 = %g and dv = %g must be finite, dv != 0",
                            orr_prob_kind_name(sel->prob), sel->prob_field, sel->v0, sel->dv);
        return ORR_OK;
    }
    return orr_fail(err, ORR_ERR_USAGE, "unknown probability kind %d", (int)sel->prob);
}

static orr_status check_ssp(const orr_pop_ssp *ssp, const char *field, orr_error *err)
{
    if (!orr_named_has(orr_ssp_clock_names, (int)ssp->clock))
        return orr_fail(err, ORR_ERR_USAGE, "ssp of '%s': unknown clock %d", field, (int)ssp->clock);
    if (ssp->clock != ORR_SSP_CLOCK_SCALE_FACTOR && !(ssp->unit_yr > 0 && isfinite(ssp->unit_yr)))
        return orr_fail(err, ORR_ERR_USAGE, "ssp of '%s': unit_yr = %g must be a number > 0", field, ssp->unit_yr);
    if (ssp->has_now && !isfinite(ssp->now))
        return orr_fail(err, ORR_ERR_USAGE, "ssp of '%s': now = %g is not a finite number", field, ssp->now);
    if (ssp->clock == ORR_SSP_CLOCK_SCALE_FACTOR) {
        if (ssp->has_now && !(ssp->now > 0))
            return orr_fail(err, ORR_ERR_USAGE, "ssp of '%s': now = %g is not a scale factor (> 0)", field, ssp->now);
        if (!(ssp->h >= 0.2 && ssp->h <= 2) || !(ssp->omega_m > 0 && ssp->omega_m <= 1))
            return orr_fail(err, ORR_ERR_USAGE,
                            "ssp of '%s': cosmology h = %g, omega_m = %g: expected h in [0.2, 2], omega_m in (0, 1]",
                            field, ssp->h, ssp->omega_m);
    }
    if (ssp->metallicity_field[0] && !NAME_SET(ssp->metallicity_field))
        return orr_fail(err, ORR_ERR_USAGE, "ssp of '%s': metallicity field name too long", field);
    if (!ssp->metallicity_field[0] && !(ssp->metallicity >= 0 && ssp->metallicity < 1))
        return orr_fail(err, ORR_ERR_USAGE, "ssp of '%s': metallicity %g must be a mass fraction in [0, 1)", field,
                        ssp->metallicity);
    return ORR_OK;
}

static orr_status check_colour(const orr_pop_colour *col, double xyz[3], orr_error *err)
{
    xyz[0] = xyz[1] = xyz[2] = 0;
    switch (col->kind) {
    case ORR_POPCOLOUR_FIXED:
        return orr_colour_xyz(&col->fixed, xyz, err);
    case ORR_POPCOLOUR_TEMPERATURE:
    case ORR_POPCOLOUR_BV:
        if (!NAME_SET(col->field))
            return orr_fail(err, ORR_ERR_USAGE, "colour from a %s field needs the field's name",
                            col->kind == ORR_POPCOLOUR_BV ? "B-V" : "temperature");
        if ((unsigned)col->cmf > ORR_CMF_JUDD_VOS || (unsigned)col->bv_rel > ORR_BV_BALLESTEROS)
            return orr_fail(err, ORR_ERR_USAGE, "colour: unknown CMF set %d or B-V relation %d", (int)col->cmf,
                            (int)col->bv_rel);
        return ORR_OK;
    case ORR_POPCOLOUR_SSP:
        if (!NAME_SET(col->field))
            return orr_fail(err, ORR_ERR_USAGE, "colour from a stellar population needs its age or formation field");
        return check_ssp(&col->ssp, col->field, err);
    }
    return orr_fail(err, ORR_ERR_USAGE, "unknown colour kind %d", (int)col->kind);
}

static orr_status check_luminance(const orr_pop_luminance *lum, orr_error *err)
{
    if (!(lum->scale > 0) || isinf(lum->scale))
        return orr_fail(err, ORR_ERR_USAGE, "luminance scale %g must be > 0", lum->scale);
    switch (lum->kind) {
    case ORR_POPLUM_CONSTANT:
    case ORR_POPLUM_MASS:
    case ORR_POPLUM_SSP:
        return ORR_OK;
    case ORR_POPLUM_FIELD:
    case ORR_POPLUM_MAGNITUDE:
        if (!NAME_SET(lum->field))
            return orr_fail(err, ORR_ERR_USAGE, "luminance from a field needs the field's name");
        return ORR_OK;
    }
    return orr_fail(err, ORR_ERR_USAGE, "unknown luminance kind %d", (int)lum->kind);
}

orr_status orr_population_add(orr_population_set *s, const orr_population *p, orr_error *err)
{
    if (!NAME_SET(p->name))
        return orr_fail(err, ORR_ERR_USAGE, "population: a name is needed (at most %d characters)",
                        ORR_POPULATION_NAME_MAX - 1);
    if (orr_population_find(s, p->name) >= 0)
        return orr_fail(err, ORR_ERR_USAGE, "population '%s' is defined twice", p->name);
    if (s->n >= ORR_POPULATION_MAX)
        return orr_fail(err, ORR_ERR_USAGE, "population '%s': at most %d populations", p->name, ORR_POPULATION_MAX);
    double xyz[3];
    orr_status st = check_select(&p->select, err);
    if (st == ORR_OK)
        st = check_colour(&p->colour, xyz, err);
    if (st == ORR_OK)
        st = check_luminance(&p->lum, err);
    if (st == ORR_OK && p->lum.kind == ORR_POPLUM_SSP && p->colour.kind != ORR_POPCOLOUR_SSP)
        st = orr_fail(err, ORR_ERR_USAGE, "luminance from a stellar population needs the colour from one (ssp)");
    if (st != ORR_OK)
        return orr_fail_prefix(err, "population '%s': ", p->name);
    int i = s->n++;
    s->pop[i] = *p;
    s->salt[i] = orr_name_salt(p->name);
    memcpy(s->fixed_xyz[i], xyz, sizeof xyz);
    return ORR_OK;
}

/* ---- assigning ------------------------------------------------------------------ */

/* The chunk arrays a population's rules read, looked up once per call. */
typedef struct bound_pop {
    const float *range, *prob, *colour, *lum;
    const float *metallicity; /* SSP colours with a metallicity field */
    double now;               /* SSP colours: now, in the field's units */
    double t_now_yr;          /* SSP from scale factors: the cosmic time of now */
    uint64_t key;             /* of the random draw */
} bound_pop;

static orr_status bind_field(const orr_chunk *c, const char *pop, const char *role, const char *name,
                             const float **out, orr_error *err)
{
    *out = orr_chunk_field(c, name);
    if (!*out)
        return orr_fail(err, ORR_ERR_USAGE, "population '%s': the particles have no field '%s' (%s)", pop, name,
                        role);
    return ORR_OK;
}

/* An SSP colour's metallicity field and its "now": its own, or the
 * snapshot's, which must then be known. */
static orr_status bind_ssp(const orr_population *p, double snapshot_time, const orr_chunk *c, bound_pop *b,
                           orr_error *err)
{
    const orr_pop_ssp *ssp = &p->colour.ssp;
    if (ssp->metallicity_field[0]) {
        orr_status st = bind_field(c, p->name, "metallicity", ssp->metallicity_field, &b->metallicity, err);
        if (st != ORR_OK)
            return st;
    }
    if (ssp->clock == ORR_SSP_CLOCK_AGE)
        return ORR_OK;
    b->now = ssp->has_now ? ssp->now : snapshot_time;
    const char *what = ssp->clock == ORR_SSP_CLOCK_TIME ? "formation time" : "formation scale factor";
    if (isnan(b->now))
        return orr_fail(err, ORR_ERR_USAGE,
                        "population '%s': ages from the %s '%s' need the time now: the snapshot has none, so give "
                        "ssp.now",
                        p->name, what, p->colour.field);
    if (ssp->clock == ORR_SSP_CLOCK_SCALE_FACTOR) {
        if (!(b->now > 0))
            return orr_fail(err, ORR_ERR_USAGE,
                            "population '%s': ages from the %s '%s': the snapshot's time %g is not a scale factor "
                            "(> 0); give ssp.now",
                            p->name, what, p->colour.field, b->now);
        b->t_now_yr = orr_cosmic_time_yr(b->now, ssp->h, ssp->omega_m);
    }
    return ORR_OK;
}

static orr_status bind_all(const orr_population_set *s, double snapshot_time, const orr_chunk *c, bound_pop *b,
                           orr_error *err)
{
    for (int k = 0; k < s->n; k++) {
        const orr_population *p = &s->pop[k];
        orr_status st = ORR_OK;
        b[k] = (bound_pop){.key = draw_key(s->seed, s->salt[k])};
        if (p->select.range_field[0])
            st = bind_field(c, p->name, "range", p->select.range_field, &b[k].range, err);
        if (st == ORR_OK && p->select.random && p->select.prob != ORR_PROB_CONSTANT)
            st = bind_field(c, p->name, "probability", p->select.prob_field, &b[k].prob, err);
        if (st == ORR_OK && p->colour.kind != ORR_POPCOLOUR_FIXED)
            st = bind_field(c, p->name, "colour", p->colour.field, &b[k].colour, err);
        if (st == ORR_OK && p->colour.kind == ORR_POPCOLOUR_SSP)
            st = bind_ssp(p, snapshot_time, c, &b[k], err);
        if (st == ORR_OK && (p->lum.kind == ORR_POPLUM_MASS || p->lum.kind == ORR_POPLUM_SSP))
            b[k].lum = c->mass;
        if (st == ORR_OK && (p->lum.kind == ORR_POPLUM_FIELD || p->lum.kind == ORR_POPLUM_MAGNITUDE))
            st = bind_field(c, p->name, "luminance", p->lum.field, &b[k].lum, err);
        if (st != ORR_OK)
            return st;
    }
    return ORR_OK;
}

static int selects(const orr_population_set *s, int k, const bound_pop *b, uint64_t id, unsigned type, size_t j)
{
    const orr_pop_select *sel = &s->pop[k].select;
    if (sel->types && (type >= 32 || !(sel->types >> type & 1u)))
        return 0;
    if (sel->has_id_range && (id < sel->id_min || id > sel->id_max))
        return 0;
    if (b->range && !(b->range[j] >= sel->field_min && b->range[j] <= sel->field_max))
        return 0;
    if (sel->random) {
        double p = orr_pop_probability(sel, b->prob ? b->prob[j] : 0);
        if (!(keyed_uniform(id, b->key) < p))
            return 0;
    }
    return 1;
}

static orr_status data_error(const orr_chunk *c, size_t j, const orr_population *p, const char *what,
                             const char *field, double v, orr_error *err)
{
    return orr_fail(err, ORR_ERR_DATA, "particle %llu (id %llu), population '%s': %s '%s' = %g is not usable",
                    (unsigned long long)(c->first_index + j), (unsigned long long)c->id[j], p->name, what, field,
                    v);
}

/* The age in years of particle j of an SSP colour, or NaN when its field
 * cannot give one (NaN, or a formation scale factor not > 0). */
static double particle_age_yr(const orr_pop_ssp *ssp, const bound_pop *b, size_t j)
{
    double v = b->colour[j];
    switch (ssp->clock) {
    case ORR_SSP_CLOCK_AGE:
        return v * ssp->unit_yr;
    case ORR_SSP_CLOCK_TIME:
        return (b->now - v) * ssp->unit_yr;
    case ORR_SSP_CLOCK_SCALE_FACTOR:
        return b->t_now_yr - orr_cosmic_time_yr(v, ssp->h, ssp->omega_m);
    }
    return NAN;
}

/* The SSP colour (Y = 1) and V luminance per unit mass of particle j. */
static orr_status ssp_colour(const orr_population *p, const bound_pop *b, const orr_chunk *c, size_t j,
                             double xyz[3], double *lv_per_mass, orr_error *err)
{
    const orr_pop_ssp *ssp = &p->colour.ssp;
    double z = b->metallicity ? b->metallicity[j] : ssp->metallicity;
    if (isnan(z))
        return data_error(c, j, p, "metallicity", ssp->metallicity_field, z, err);
    double age = particle_age_yr(ssp, b, j);
    orr_ssp_colour pop;
    if (!orr_ssp_lookup(age, z, &pop) || !orr_blackbody_xyz(orr_bv_to_teff(pop.bv, p->colour.bv_rel), p->colour.cmf, xyz))
        return data_error(c, j, p, orr_named_name(orr_ssp_clock_names, (int)ssp->clock), p->colour.field,
                          b->colour[j], err);
    *lv_per_mass = pop.lv_per_msun;
    return ORR_OK;
}

/* Colour (Y = 1) of particle j in population k; for SSP colours also the
 * V luminance per unit mass (else 1). */
static orr_status particle_colour(const orr_population_set *s, int k, const bound_pop *b, const orr_chunk *c,
                                  size_t j, double xyz[3], double *lv_per_mass, orr_error *err)
{
    const orr_pop_colour *col = &s->pop[k].colour;
    double v;
    *lv_per_mass = 1;
    switch (col->kind) {
    case ORR_POPCOLOUR_SSP:
        return ssp_colour(&s->pop[k], b, c, j, xyz, lv_per_mass, err);
    case ORR_POPCOLOUR_TEMPERATURE:
        v = b->colour[j];
        if (!(v > 0) || !orr_blackbody_xyz(v, col->cmf, xyz))
            return data_error(c, j, &s->pop[k], "temperature", col->field, v, err);
        return ORR_OK;
    case ORR_POPCOLOUR_BV:
        v = b->colour[j];
        if (!isfinite(v) || !orr_blackbody_xyz(orr_bv_to_teff(v, col->bv_rel), col->cmf, xyz))
            return data_error(c, j, &s->pop[k], "B-V", col->field, v, err);
        return ORR_OK;
    default:
        memcpy(xyz, s->fixed_xyz[k], 3 * sizeof *xyz);
        return ORR_OK;
    }
}

static orr_status particle_luminance(const orr_population *p, const bound_pop *b, const orr_chunk *c, size_t j,
                                     double lv_per_mass, double *lum, orr_error *err)
{
    double v = b->lum ? b->lum[j] : 1;
    double l;
    switch (p->lum.kind) {
    case ORR_POPLUM_SSP:
        l = p->lum.scale * v * lv_per_mass;
        break;
    case ORR_POPLUM_MAGNITUDE:
        l = p->lum.scale * pow(10.0, -0.4 * v);
        break;
    case ORR_POPLUM_CONSTANT:
        l = p->lum.scale;
        break;
    default:
        l = p->lum.scale * v;
        break;
    }
    if (!(l >= 0) || isinf(l))
        return data_error(c, j, p, "luminance from",
                          p->lum.kind == ORR_POPLUM_MASS || p->lum.kind == ORR_POPLUM_SSP ? "mass" : p->lum.field, v,
                          err);
    *lum = l;
    return ORR_OK;
}

orr_status orr_population_assign(const orr_population_set *s, const orr_chunk *c, size_t start, size_t count,
                                 int only, int32_t *pop, float *X, float *Y, float *Z, orr_error *err)
{
    return orr_population_assign_at(s, NAN, c, start, count, only, pop, X, Y, Z, err);
}

orr_status orr_population_assign_at(const orr_population_set *s, double snapshot_time, const orr_chunk *c,
                                    size_t start, size_t count, int only, int32_t *pop, float *X, float *Y, float *Z,
                                    orr_error *err)
{
    if (start > c->n || count > c->n - start)
        return orr_fail(err, ORR_ERR_INTERNAL, "population: particles %zu..%zu outside a chunk of %zu", start,
                        start + count, c->n);
    bound_pop b[ORR_POPULATION_MAX];
    orr_status st = bind_all(s, snapshot_time, c, b, err);
    if (st != ORR_OK)
        return st;
    for (size_t i = 0; i < count; i++) {
        size_t j = start + i;
        int k = 0;
        while (k < s->n && !selects(s, k, &b[k], c->id[j], c->type[j], j))
            k++;
        if (k == s->n)
            k = -1;
        if (pop)
            pop[i] = k;
        double xyz[3] = {0, 0, 0}, lum = 0, lv_per_mass;
        if (k >= 0 && (only < 0 || only == k)) {
            st = particle_colour(s, k, &b[k], c, j, xyz, &lv_per_mass, err);
            if (st == ORR_OK)
                st = particle_luminance(&s->pop[k], &b[k], c, j, lv_per_mass, &lum, err);
            if (st != ORR_OK)
                return st;
        }
        X[i] = (float)(lum * xyz[0]);
        Y[i] = (float)(lum * xyz[1]);
        Z[i] = (float)(lum * xyz[2]);
    }
    return ORR_OK;
}
