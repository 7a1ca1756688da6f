#include "core/names.h"

#include <string.h>

int orr_named_value(const orr_named *table, const char *name, int *value)
{
    if (!name)
        return 0;
    for (const orr_named *n = table; n->name; n++)
        if (strcmp(n->name, name) == 0) {
            *value = n->value;
            return 1;
        }
    return 0;
}

int orr_named_has(const orr_named *table, int value)
{
    for (const orr_named *n = table; n->name; n++)
        if (n->value == value)
            return 1;
    return 0;
}

const char *orr_named_name(const orr_named *table, int value)
{
    for (const orr_named *n = table; n->name; n++)
        if (n->value == value)
            return n->name;
    return "unknown";
}

const char *orr_named_list(const orr_named *table, char *buf, size_t size)
{
    size_t used = 0;
    if (size == 0)
        return buf;
    buf[0] = '\0';
    for (const orr_named *n = table; n->name; n++) {
        if (orr_named_name(table, n->value) != n->name)
            continue; /* an alias */
        size_t len = strlen(n->name), sep = used > 0;
        if (used + sep + len + 1 > size)
            break;
        if (sep)
            buf[used++] = ' ';
        memcpy(buf + used, n->name, len + 1);
        used += len;
    }
    return buf;
}
