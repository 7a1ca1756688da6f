/* madvise's MADV_HUGEPAGE is a Linux extension, beyond POSIX. */
#define _DEFAULT_SOURCE
#include "core/plane.h"

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>

/* Planes of at least LARGE_PLANE bytes are aligned to HUGE_PAGE bytes and
 * zeroed on every thread, so their pages are faulted in during set-up by
 * all threads at once, not by the deposit. Planes of at least HUGE_PLANE
 * bytes (an 8192^2 plane, 268 MB) also go on transparent huge pages where
 * the system offers them: a deposit adds to pixels all over the image, and
 * with 4 KiB pages such a plane spans 65 000 pages, far more than the TLB
 * holds (without them the 8K frame's deposit took 5 % longer). Smaller
 * planes stay on 4 KiB pages: their deposits were no slower so (the 3600^2
 * dome master and 4096 x 2048 panorama at 2 x 10^6 and 10^7 particles),
 * while a huge page's first touch can cost several times as much as 512
 * small ones (a virtual machine backing fresh memory on demand: the
 * README's main job's set-up 2.1 -> 1.0 s, docs/performance.md). */
#define HUGE_PAGE ((size_t)2 << 20)
#define LARGE_PLANE (2 * HUGE_PAGE)
#define HUGE_PLANE ((size_t)128 << 20)

/* Zeroes memory a huge page at a time on every thread. On a fresh
 * allocation the first touch of each page is a fault in which the kernel
 * clears it, and one thread alone clearing an 8192^2 dome master's three
 * planes (805 MB) took most of a frame's set-up; a plane cleared again for
 * the next frame keeps the pages where the same threads first touched
 * them. */
static void zero_on_every_thread(unsigned char *mem, size_t bytes)
{
    size_t pages = (bytes + HUGE_PAGE - 1) / HUGE_PAGE;
#pragma omp parallel for schedule(static)
    for (size_t k = 0; k < pages; k++) {
        size_t start = k * HUGE_PAGE, len = bytes - start < HUGE_PAGE ? bytes - start : HUGE_PAGE;
        memset(mem + start, 0, len);
    }
}

/* n zeroed floats. */
static float *plane_memory(size_t n, orr_error *err)
{
#ifdef MADV_HUGEPAGE
    size_t bytes = n * sizeof(float);
    if (bytes >= LARGE_PLANE) {
        size_t rounded = (bytes + HUGE_PAGE - 1) / HUGE_PAGE * HUGE_PAGE;
        void *mem = NULL;
        if (posix_memalign(&mem, HUGE_PAGE, rounded) != 0) {
            orr_fail(err, ORR_ERR_NOMEM, "out of memory (%zu bytes for image plane)", rounded);
            return NULL;
        }
        if (bytes >= HUGE_PLANE)
            madvise(mem, rounded, MADV_HUGEPAGE); /* advice: no harm if refused */
        zero_on_every_thread(mem, bytes);
        return mem;
    }
#endif
    return orr_calloc(n, sizeof(float), "image plane", err);
}

orr_status orr_plane_alloc(orr_plane *p, int width, int height, const char *name, const char *unit,
                           orr_error *err)
{
    memset(p, 0, sizeof *p);
    if (width <= 0 || height <= 0 || width > 65536 || height > 65536)
        return orr_fail(err, ORR_ERR_USAGE, "image size %d x %d is out of range (1 to 65536 pixels a side)",
                        width, height);
    /* Deposits address pixels with 32-bit indices (splat/deposit.h). */
    if ((size_t)width * (size_t)height > (size_t)INT32_MAX)
        return orr_fail(err, ORR_ERR_USAGE,
                        "image size %d x %d has more than 2^31 - 1 pixels (8 GiB a plane), the most orrery draws",
                        width, height);
    p->data = plane_memory((size_t)width * (size_t)height, err);
    if (!p->data)
        return ORR_ERR_NOMEM;
    p->width = width;
    p->height = height;
    snprintf(p->name, sizeof p->name, "%s", name ? name : "");
    snprintf(p->unit, sizeof p->unit, "%s", unit ? unit : "");
    return ORR_OK;
}

void orr_plane_clear(orr_plane *p)
{
    size_t bytes = (size_t)p->width * (size_t)p->height * sizeof(float);
    if (bytes >= LARGE_PLANE)
        zero_on_every_thread((unsigned char *)p->data, bytes);
    else
        memset(p->data, 0, bytes);
}

void orr_plane_free(orr_plane *p)
{
    free(p->data);
    p->data = NULL;
}

double orr_plane_sum(const orr_plane *p)
{
    double s = 0;
    size_t n = (size_t)p->width * (size_t)p->height;
    for (size_t i = 0; i < n; i++)
        s += p->data[i];
    return s;
}
