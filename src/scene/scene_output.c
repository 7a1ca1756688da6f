#include "scene/scene_output.h"

#include <string.h>

/* A weight unit is a product of FITS unit symbols with powers and a scale
 * ("solMass", "10**10 solMass", "erg s-1"): letters, digits, spaces and
 * "*", ".", "+", "-". A "/" is refused, since BUNIT appends " sr-1" and a
 * FITS "/" divides by everything after it. Returns the first bad character,
 * or 0. */
static char bad_unit_char(const char *u)
{
    for (const char *c = u; *c; c++)
        if (!strchr("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789 *.+-", *c))
            return *c;
    return 0;
}

/* A length unit is one symbol ("kpc", "Mpc", "m", "AU"), since BUNIT squares
 * it as "kpc-2". */
static int is_symbol(const char *u)
{
    if (!u[0])
        return 0;
    for (const char *c = u; *c; c++)
        if (!((*c >= 'a' && *c <= 'z') || (*c >= 'A' && *c <= 'Z')))
            return 0;
    return 1;
}

orr_status scene_check_output_units(const orr_scene *s, const scene_marks *m, orr_error *err)
{
    char bad = bad_unit_char(s->bunit);
    if (bad == '/')
        return scene_fail_key(s, m, "output.bunit", err,
                              "output.bunit: '%s' divides with '/'; write a FITS unit with negative powers "
                              "instead, e.g. 'solMass yr-1'",
                              s->bunit);
    if (bad)
        return scene_fail_key(s, m, "output.bunit", err,
                              "output.bunit: '%s' is not a FITS unit string (it has '%c'); e.g. 'solMass', "
                              "'10**10 solMass' or 'solLum'",
                              s->bunit, bad);
    if (s->length_unit[0] && !is_symbol(s->length_unit))
        return scene_fail_key(s, m, "output.length_unit", err,
                              "output.length_unit: '%s' is not a single FITS unit symbol such as kpc, Mpc, pc or m",
                              s->length_unit);
    return ORR_OK;
}

const char *scene_weight_unit(const orr_scene *s)
{
    if (s->bunit[0])
        return s->bunit;
    int weighs_mass = strcmp(s->weight, "mass") == 0 && !s->colour && !s->nlayers;
    return s->model_name[0] && weighs_mass ? "10**10 solMass" : "";
}

const char *scene_length_unit(const orr_scene *s)
{
    if (s->length_unit[0])
        return s->length_unit;
    return s->model_name[0] ? "kpc" : "";
}
