/* Numbers in text, whatever the host program's locale. A program that
 * embeds the library may call setlocale(LC_ALL, "de_DE.UTF-8"), after which
 * strtod stops at the '.' of "4.5" and printf writes "4,5": scene files,
 * FITS cards, text tables and metadata would be misread or miswritten. So
 * every number read from or written to such text goes through these, which
 * use the C locale ('.' as the decimal point, no grouping) in any thread,
 * without touching the program's own locale. */
#ifndef ORR_CORE_NUMBERS_H
#define ORR_CORE_NUMBERS_H

#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>

/* strtod in the C locale: the same forms ("4.5", "-1e-3", "inf", "nan",
 * hex floats) and the same *end. */
double orr_strtod(const char *text, char **end);

/* Parses all of text as one number in the C locale; returns 1 and *out,
 * or 0 when text is empty or has anything after the number. */
int orr_parse_double(const char *text, double *out);

/* snprintf, vsnprintf and fprintf in the C locale, for numbers written to
 * files and headers. */
int orr_snprintf(char *buf, size_t size, const char *fmt, ...) __attribute__((format(printf, 3, 4)));
int orr_vsnprintf(char *buf, size_t size, const char *fmt, va_list ap) __attribute__((format(printf, 3, 0)));
int orr_fprintf(FILE *fp, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

/* For a run of many formatting calls (a text table's rows), cheaper than
 * switching for each: the calling thread formats in the C locale from
 * orr_c_locale_enter until orr_c_locale_leave(what enter returned). */
void *orr_c_locale_enter(void);
void orr_c_locale_leave(void *saved);

#endif
