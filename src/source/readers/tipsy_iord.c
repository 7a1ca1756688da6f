/* Tipsy's .iord id array (tipsy_iord.h). */
#include "source/readers/tipsy_iord.h"

#include <errno.h>
#include <inttypes.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "core/bytes.h"

#define IORD_LINE_MAX 64 /* an ASCII line: a 64-bit id and some blanks */

/* Reads one ASCII line into buf; 0 at the end of the file. */
static int read_line(orr_tipsy_iord *a, char *buf, size_t size)
{
    if (!fgets(buf, (int)size, a->fp))
        return 0;
    a->line++;
    return 1;
}

/* Parses one line's integer: blanks, digits, blanks. Returns 0 when the
 * line is not that (a sign, a fraction, a second number, too long). */
static int parse_id(const char *buf, uint64_t *v)
{
    const char *p = buf + strspn(buf, " \t");
    if (*p < '0' || *p > '9')
        return 0;
    char *end;
    errno = 0;
    unsigned long long u = strtoull(p, &end, 10);
    if (errno == ERANGE)
        return 0;
    end += strspn(end, " \t\r\n");
    if (*end)
        return 0;
    *v = (uint64_t)u;
    return 1;
}

/* Positions an ASCII file at its first id (line 2). */
static orr_status ascii_restart(orr_tipsy_iord *a, int64_t nbodies, orr_error *err)
{
    char buf[IORD_LINE_MAX];
    uint64_t count = 0;
    rewind(a->fp);
    a->line = 0;
    if (!read_line(a, buf, sizeof buf) || !parse_id(buf, &count))
        return orr_fail(err, ORR_ERR_FORMAT,
                        "%s: neither a binary id array (its size is not 4 + 4 or 8 bytes per particle) nor an ASCII "
                        "one (line 1 is not the particle count)",
                        a->path);
    if (count != (uint64_t)nbodies)
        return orr_fail(err, ORR_ERR_FORMAT, "%s: line 1 says %" PRIu64 " particles but the snapshot has %" PRId64,
                        a->path, count, nbodies);
    a->next = 0;
    return ORR_OK;
}

/* Whether a binary file of size bytes with this count header fits nbodies
 * ids of 4 or 8 bytes in byte order swap; sets a->width. */
static int binary_fits(orr_tipsy_iord *a, const unsigned char head[4], long long size, int64_t nbodies, int swap)
{
    int32_t count = orr_load_i32(head, swap);
    if (count != nbodies)
        return 0;
    for (int width = 4; width <= 8; width += 4)
        if (size == 4 + (long long)width * nbodies) {
            a->width = width;
            a->swap = swap;
            return 1;
        }
    return 0;
}

orr_status orr_tipsy_iord_open(orr_tipsy_iord *a, const char *snapshot, int64_t nbodies, int *found,
                               orr_error *err)
{
    memset(a, 0, sizeof *a);
    *found = 0;
    int n = snprintf(a->path, sizeof a->path, "%s.iord", snapshot);
    struct stat sb;
    if (n < 0 || (size_t)n >= sizeof a->path || stat(a->path, &sb) != 0)
        return ORR_OK; /* no id array: ids are file positions */
    if (!S_ISREG(sb.st_mode))
        return orr_fail(err, ORR_ERR_IO, "%s: not a regular file", a->path);
    if (!(a->fp = fopen(a->path, "rb")))
        return orr_fail(err, ORR_ERR_IO, "%s: cannot open: %s", a->path, strerror(errno));
    *found = 1;
    unsigned char head[4] = {0};
    int host_big = orr_host_big_endian();
    /* Big-endian (XDR) first, as ChaNGa writes; the count decides. */
    if (fread(head, 1, 4, a->fp) == 4 &&
        (binary_fits(a, head, (long long)sb.st_size, nbodies, !host_big) ||
         binary_fits(a, head, (long long)sb.st_size, nbodies, host_big))) {
        a->binary = 1;
        return ORR_OK;
    }
    return ascii_restart(a, nbodies, err);
}

static orr_status read_binary(orr_tipsy_iord *a, int64_t first, size_t n, uint64_t *out, orr_error *err)
{
    unsigned char buf[8 * 512];
    if (fseeko(a->fp, (off_t)(4 + first * a->width), SEEK_SET) != 0)
        return orr_fail(err, ORR_ERR_IO, "%s: cannot seek to id %" PRId64 ": %s", a->path, first, strerror(errno));
    for (size_t done = 0; done < n;) {
        size_t k = n - done < 512 ? n - done : 512;
        if (fread(buf, (size_t)a->width, k, a->fp) != k)
            return orr_fail(err, ORR_ERR_FORMAT, "%s: ends before id %" PRId64 " (the file shrank?)", a->path,
                            first + (int64_t)done);
        for (size_t i = 0; i < k; i++) {
            const unsigned char *p = buf + i * (size_t)a->width;
            int64_t v = a->width == 4 ? orr_load_i32(p, a->swap) : (int64_t)orr_load_u64(p, a->swap);
            if (v < 0)
                return orr_fail(err, ORR_ERR_FORMAT, "%s: id %" PRId64 " of particle %" PRId64 " is negative",
                                a->path, v, first + (int64_t)(done + i));
            out[done + i] = (uint64_t)v;
        }
        done += k;
    }
    return ORR_OK;
}

static orr_status read_ascii(orr_tipsy_iord *a, int64_t first, size_t n, uint64_t *out, orr_error *err)
{
    char buf[IORD_LINE_MAX];
    if (first < a->next) { /* a rewind: from the first id again (the count was checked when opened) */
        rewind(a->fp);
        a->line = 0;
        a->next = 0;
        if (!read_line(a, buf, sizeof buf))
            return orr_fail(err, ORR_ERR_FORMAT, "%s: empty (the file changed?)", a->path);
    }
    for (; a->next < first + (int64_t)n; a->next++) {
        uint64_t v;
        if (!read_line(a, buf, sizeof buf))
            return orr_fail(err, ORR_ERR_FORMAT, "%s: ends at line %ld, before the id of particle %" PRId64, a->path,
                            a->line, a->next);
        if (!parse_id(buf, &v))
            return orr_fail(err, ORR_ERR_FORMAT, "%s:%ld: not an id (one integer, not negative, a line)", a->path,
                            a->line);
        if (a->next >= first)
            out[a->next - first] = v;
    }
    return ORR_OK;
}

orr_status orr_tipsy_iord_read(orr_tipsy_iord *a, int64_t first, size_t n, uint64_t *out, orr_error *err)
{
    return a->binary ? read_binary(a, first, n, out, err) : read_ascii(a, first, n, out, err);
}

void orr_tipsy_iord_close(orr_tipsy_iord *a)
{
    if (a->fp)
        fclose(a->fp);
    a->fp = NULL;
}
