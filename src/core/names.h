/* One table of {name, value} per enumeration, owned by the stage that
 * defines the enumeration and used for parsing scene words, for the
 * "one of: ..." of error messages and for the names written into FITS
 * cards and reports, so that each name is written once. A table ends with
 * {NULL, 0}. */
#ifndef ORR_CORE_NAMES_H
#define ORR_CORE_NAMES_H

#include <stddef.h>

typedef struct orr_named {
    const char *name;
    int value;
} orr_named;

/* Sets *value to the value named `name` and returns 1; returns 0 (leaving
 * *value alone) on NULL or an unknown name. */
int orr_named_value(const orr_named *table, const char *name, int *value);

/* 1 when some entry has `value` (a check that an enumeration is in range). */
int orr_named_has(const orr_named *table, int value);

/* The first name of `value`, or "unknown". */
const char *orr_named_name(const orr_named *table, int value);

/* The table's names separated by single spaces ("ngp cic sph"), written
 * into buf (truncated to size); returns buf. A later name of a value
 * already named is an alias ("gray" after "grey"): it is parsed but not
 * listed. */
const char *orr_named_list(const orr_named *table, char *buf, size_t size);

/* Defines `int fn(const char *name, type *out)`, the typed parser of an
 * enumeration from its table: 1 and *out set when the name is known. */
#define ORR_NAMED_PARSER(fn, type, table)                                                                    \
    int fn(const char *name, type *out)                                                                      \
    {                                                                                                        \
        int value_;                                                                                          \
        if (!orr_named_value((table), name, &value_))                                                        \
            return 0;                                                                                        \
        *out = (type)value_;                                                                                 \
        return 1;                                                                                            \
    }

#endif
