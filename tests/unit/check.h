/* A minimal test harness: CHECK macros count failures and print where they
 * happened; TEST_MAIN runs the listed test functions and prints a summary. */
#ifndef ORR_TEST_CHECK_H
#define ORR_TEST_CHECK_H

#include <math.h>
#include <stdio.h>
#include <string.h>

static int check_failures = 0;
static int check_count = 0;

#define CHECK(cond)                                                                   \
    do {                                                                              \
        check_count++;                                                                \
        if (!(cond)) {                                                                \
            check_failures++;                                                         \
            fprintf(stderr, "%s:%d: check failed: %s\n", __FILE__, __LINE__, #cond);  \
        }                                                                             \
    } while (0)

#define CHECK_NEAR(a, b, tol)                                                                   \
    do {                                                                                        \
        check_count++;                                                                          \
        double check_a_ = (double)(a), check_b_ = (double)(b);                                  \
        if (!(fabs(check_a_ - check_b_) <= (tol))) {                                            \
            check_failures++;                                                                   \
            fprintf(stderr, "%s:%d: %s = %.10g, expected %s = %.10g (tolerance %g)\n", __FILE__, \
                    __LINE__, #a, check_a_, #b, check_b_, (double)(tol));                       \
        }                                                                                       \
    } while (0)

/* Checks that haystack contains needle (e.g. an error message names a key). */
#define CHECK_CONTAINS(haystack, needle)                                                   \
    do {                                                                                   \
        check_count++;                                                                     \
        if (!strstr((haystack), (needle))) {                                               \
            check_failures++;                                                              \
            fprintf(stderr, "%s:%d: \"%s\" does not contain \"%s\"\n", __FILE__, __LINE__, \
                    (haystack), (needle));                                                 \
        }                                                                                  \
    } while (0)

#define RUN(test)                                  \
    do {                                           \
        int before_ = check_failures;              \
        test();                                    \
        fprintf(stderr, "%s %s\n", check_failures == before_ ? "ok  " : "FAIL", #test); \
    } while (0)

/* The path of a shared reference file, or NULL (after saying so) when the
 * shared data folder is absent; tests then exit with SKIP_CODE. */
#define SKIP_CODE 77
static inline const char *shared_data_path(char *buf, size_t size, const char *relative)
{
#ifdef ORRERY_SHARED_DATA
    snprintf(buf, size, "%s/%s", ORRERY_SHARED_DATA, relative);
    FILE *fp = fopen(buf, "rb");
    if (fp) {
        fclose(fp);
        return buf;
    }
#endif
    fprintf(stderr, "shared reference file %s not found: skipping\n", relative);
    (void)buf;
    (void)size;
    return NULL;
}

static inline int check_summary(void)
{
    fprintf(stderr, "%d checks, %d failed\n", check_count, check_failures);
    return check_failures ? 1 : 0;
}

#endif
