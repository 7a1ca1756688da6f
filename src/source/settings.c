#include "source/settings.h"

#include <stdio.h>
#include <string.h>

#include "core/owned.h"

#define COUNT(a) (sizeof(a) / sizeof((a)[0]))

const orr_named orr_nonfinite_names[] = {{"error", 0}, {"skip", 1}, {NULL, 0}};

static const char *const SEQUENCE_KEYS[] = {
    "input.sequence.pattern", "input.sequence.first", "input.sequence.last", "input.sequence.step",
    "input.sequence.files", "input.sequence.interpolation", "input.sequence.max_memory",
};
static const char *const RANGE_KEYS[] = {"input.sequence.first", "input.sequence.last", "input.sequence.step"};

/* Each built-in model has its own parameters: another model's are errors. */
static orr_status check_model_keys(const orr_input_settings *in, const orr_keys *keys, orr_error *err)
{
    static const char *const mw_m31_only[] = {"input.model.separation", "input.model.galaxies",
                                              "input.model.disc_q", "input.model.m31_weight",
                                              "input.model.dust_particles"};
    static const char *const king_only[] = {"input.model.w0", "input.model.core_radius", "input.model.mass"};
    const int king = strcmp(in->model.name, "king") == 0;
    const char *const *foreign = king ? mw_m31_only : king_only;
    size_t nforeign = king ? COUNT(mw_m31_only) : COUNT(king_only);
    for (size_t i = 0; i < nforeign; i++)
        if (orr_key_given(keys, foreign[i]))
            return orr_fail_key(keys, foreign[i], err, "%s does not apply to input.model.name: %s", foreign[i],
                                in->model.name);
    return ORR_OK;
}

static orr_status check_source(const orr_input_settings *in, const orr_keys *keys, orr_error *err)
{
    static const char *const model_keys[] = {"input.model.particles", "input.model.seed",
                                             "input.model.separation", "input.model.w0",
                                             "input.model.core_radius", "input.model.mass",
                                             "input.model.galaxies", "input.model.disc_q",
                                             "input.model.m31_weight"};
    const int has_file = in->file != NULL, has_model = in->model.name[0] != '\0';
    const int has_sequence = orr_input_has_sequence(in);
    const char *sequence_key = in->sequence.pattern ? "input.sequence.pattern" : "input.sequence.files";
    if (has_file && has_model)
        return orr_fail_key(keys, "input.model.name", err,
                            "input.file and input.model.name are both set; use one of them");
    if (has_sequence && (has_file || has_model))
        return orr_fail_key(keys, sequence_key, err, "%s and %s are both set; use one of them", sequence_key,
                            has_file ? "input.file" : "input.model.name");
    if (!has_file && !has_model && !has_sequence && !in->insitu)
        return orr_fail_key(keys, NULL, err,
                            "no input: set input.file or input.model.name, or a sequence (input.sequence.pattern "
                            "or input.sequence.files)");
    for (size_t i = 0; !has_model && i < COUNT(model_keys); i++)
        if (orr_key_given(keys, model_keys[i]))
            return orr_fail_key(keys, model_keys[i], err, "%s applies to input.model.name, but the input is %s",
                                model_keys[i], has_file ? "input.file" : sequence_key);
    return has_model ? check_model_keys(in, keys, err) : ORR_OK;
}

/* The pattern: one integer conversion, and a range of at least 2 files. */
static orr_status check_sequence_pattern(const orr_input_settings *in, const orr_keys *keys, orr_error *err)
{
    orr_error why;
    if (orr_sequence_pattern_check(in->sequence.pattern, &why))
        return orr_fail_key(keys, "input.sequence.pattern", err, "input.sequence.pattern: %s", why.msg);
    if (!orr_key_given(keys, "input.sequence.last"))
        return orr_fail_key(keys, "input.sequence.pattern", err,
                            "input.sequence.pattern needs input.sequence.last, the number of the last snapshot");
    if (in->sequence.last < in->sequence.first)
        return orr_fail_key(keys, "input.sequence.last", err,
                            "input.sequence.last (%lld) is below input.sequence.first (%lld)", in->sequence.last,
                            in->sequence.first);
    if ((in->sequence.last - in->sequence.first) / in->sequence.step + 1 < 2)
        return orr_fail_key(keys, "input.sequence.last", err,
                            "input.sequence.first %lld, last %lld, step %lld give one snapshot; a sequence needs "
                            "at least 2 (use input.file for one)",
                            in->sequence.first, in->sequence.last, in->sequence.step);
    return ORR_OK;
}

static orr_status check_sequence(const orr_input_settings *in, const orr_keys *keys, orr_error *err)
{
    if (!orr_input_has_sequence(in)) {
        for (size_t i = 0; i < COUNT(SEQUENCE_KEYS); i++)
            if (orr_key_given(keys, SEQUENCE_KEYS[i]))
                return orr_fail_key(keys, SEQUENCE_KEYS[i], err,
                                    "%s applies to a sequence, but neither input.sequence.pattern nor "
                                    "input.sequence.files is set",
                                    SEQUENCE_KEYS[i]);
        return ORR_OK;
    }
    if (in->sequence.pattern && in->sequence.nfiles > 0)
        return orr_fail_key(keys, "input.sequence.files", err,
                            "input.sequence.pattern and input.sequence.files are both set; list the snapshots "
                            "one way");
    for (size_t i = 0; in->sequence.nfiles > 0 && i < COUNT(RANGE_KEYS); i++)
        if (orr_key_given(keys, RANGE_KEYS[i]))
            return orr_fail_key(keys, RANGE_KEYS[i], err,
                                "%s applies to input.sequence.pattern, but the snapshots are listed by "
                                "input.sequence.files",
                                RANGE_KEYS[i]);
    return in->sequence.pattern ? check_sequence_pattern(in, keys, err) : ORR_OK;
}

orr_status orr_input_prepare(const orr_input_settings *in, const orr_keys *keys, orr_error *err)
{
    orr_status st = check_source(in, keys, err);
    return st ? st : check_sequence(in, keys, err);
}

int orr_input_has_sequence(const orr_input_settings *in)
{
    return in->sequence.pattern != NULL || in->sequence.nfiles > 0;
}

const char *orr_sequence_file(const orr_sequence_settings *d, int i)
{
    const char *p = d->files;
    for (int k = 0; k < i && k < d->nfiles; k++)
        p += strlen(p) + 1;
    return p;
}

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
    d->model.m31_weight = 1;
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

int orr_input_settings_strings(orr_input_settings *d, char **fields[])
{
    fields[0] = &d->file;
    fields[1] = &d->sequence.pattern;
    return ORR_INPUT_STRINGS;
}

void orr_input_settings_free(orr_input_settings *d)
{
    char **fields[ORR_INPUT_STRINGS];
    orr_owned_free_all(fields, orr_input_settings_strings(d, fields));
}

orr_status orr_input_settings_copy(orr_input_settings *dst, const orr_input_settings *src, orr_error *err)
{
    char **fields[ORR_INPUT_STRINGS];
    return orr_owned_copy(dst, src, sizeof *dst, fields, orr_input_settings_strings(dst, fields), err);
}
