/* Locale-independent number text (see numbers.h), with glibc's per-thread
 * locales: strtod_l reads with the C locale object, and the formatting
 * functions switch the calling thread to it with uselocale for the one
 * call, then back (other threads, and the program's global locale, are
 * untouched). */
#define _GNU_SOURCE
#include "core/numbers.h"

#include <locale.h>
#include <pthread.h>
#include <stdlib.h>

static locale_t c_locale;
static pthread_once_t c_locale_once = PTHREAD_ONCE_INIT;

static void make_c_locale(void)
{
    /* "C" always exists, so newlocale does not fail for want of it; if it
     * fails for want of memory, LC_GLOBAL_LOCALE below is the fallback. */
    c_locale = newlocale(LC_ALL_MASK, "C", (locale_t)0);
}

static locale_t the_c_locale(void)
{
    pthread_once(&c_locale_once, make_c_locale);
    return c_locale;
}

double orr_strtod(const char *text, char **end)
{
    locale_t c = the_c_locale();
    return c ? strtod_l(text, end, c) : strtod(text, end);
}

int orr_parse_double(const char *text, double *out)
{
    char *end;
    double v = orr_strtod(text, &end);
    if (end == text || *end != '\0')
        return 0;
    *out = v;
    return 1;
}

int orr_vsnprintf(char *buf, size_t size, const char *fmt, va_list ap)
{
    locale_t c = the_c_locale();
    locale_t old = c ? uselocale(c) : (locale_t)0;
    int n = vsnprintf(buf, size, fmt, ap);
    if (c)
        uselocale(old);
    return n;
}

int orr_snprintf(char *buf, size_t size, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    int n = orr_vsnprintf(buf, size, fmt, ap);
    va_end(ap);
    return n;
}

int orr_fprintf(FILE *fp, const char *fmt, ...)
{
    locale_t c = the_c_locale();
    locale_t old = c ? uselocale(c) : (locale_t)0;
    va_list ap;
    va_start(ap, fmt);
    int n = vfprintf(fp, fmt, ap);
    va_end(ap);
    if (c)
        uselocale(old);
    return n;
}

void *orr_c_locale_enter(void)
{
    locale_t c = the_c_locale();
    return c ? (void *)uselocale(c) : NULL;
}

void orr_c_locale_leave(void *saved)
{
    if (saved)
        uselocale((locale_t)saved);
}
