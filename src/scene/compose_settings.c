#include "scene/compose_settings.h"

#include "core/owned.h"

int orr_compose_settings_strings(orr_compose_settings *c, char **fields[])
{
    for (int i = 0; i < ORR_COMPOSE_STRINGS; i++)
        fields[i] = &c->layers[i].file;
    return ORR_COMPOSE_STRINGS;
}

void orr_compose_settings_free(orr_compose_settings *c)
{
    char **fields[ORR_COMPOSE_STRINGS];
    orr_owned_free_all(fields, orr_compose_settings_strings(c, fields));
}

orr_status orr_compose_settings_copy(orr_compose_settings *dst, const orr_compose_settings *src, orr_error *err)
{
    char **fields[ORR_COMPOSE_STRINGS];
    return orr_owned_copy(dst, src, sizeof *dst, fields, orr_compose_settings_strings(dst, fields), err);
}
