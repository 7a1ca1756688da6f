/* ZIP archives (zip_archive.h). Field offsets are APPNOTE.TXT's (4.3.7
 * local file header, 4.3.12 central directory header, 4.3.14-16 the ZIP64
 * end records, 4.5.3 the ZIP64 extra field). */
#include "source/readers/zip_archive.h"

#include <errno.h>
#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#define SIG_LOCAL 0x04034b50u
#define SIG_CENTRAL 0x02014b50u
#define SIG_END 0x06054b50u
#define SIG_END64 0x06064b50u
#define SIG_LOCATOR64 0x07064b50u
#define END_BYTES 22
#define LOCATOR64_BYTES 20
#define END64_BYTES 56
#define CENTRAL_BYTES 46
#define LOCAL_BYTES 30
#define MAX_COMMENT 65535
#define MAX_DIRECTORY ((uint64_t)64 << 20) /* bytes of central directory read */
#define INFLATE_INPUT ((size_t)64 << 10)

static uint32_t le16(const unsigned char *p) { return (uint32_t)p[0] | (uint32_t)p[1] << 8; }
static uint32_t le32(const unsigned char *p) { return le16(p) | le16(p + 2) << 16; }
static uint64_t le64(const unsigned char *p) { return (uint64_t)le32(p) | (uint64_t)le32(p + 4) << 32; }

int orr_zip_probe(const unsigned char *head, size_t n)
{
    return n >= 4 && (le32(head) == SIG_LOCAL || (n >= END_BYTES && le32(head) == SIG_END));
}

/* Reads exactly n bytes at off; 0 on success, -1 (errno, or 0 for the
 * end of the file) otherwise. */
static int read_at(int fd, void *buf, size_t n, uint64_t off)
{
    unsigned char *p = buf;
    while (n > 0) {
        ssize_t got = pread(fd, p, n, (off_t)off);
        if (got < 0 && errno == EINTR)
            continue;
        if (got <= 0) {
            if (got == 0)
                errno = 0;
            return -1;
        }
        p += got;
        n -= (size_t)got;
        off += (uint64_t)got;
    }
    return 0;
}

static orr_status read_failed(const char *path, const char *what, orr_error *err)
{
    if (errno)
        return orr_fail(err, ORR_ERR_IO, "%s: cannot read %s: %s", path, what, strerror(errno));
    return orr_fail(err, ORR_ERR_FORMAT, "%s: the file ends inside %s", path, what);
}

/* Where the central directory is, and how many entries it has. */
typedef struct directory_place {
    uint64_t offset, size, entries;
} directory_place;

/* The ZIP64 end record the locator before the end record points at, when
 * there is one: it holds the directory's place in 64-bit fields. */
static orr_status read_end64(int fd, const char *path, uint64_t end_at, directory_place *d, orr_error *err)
{
    unsigned char loc[LOCATOR64_BYTES], rec[END64_BYTES];
    if (end_at < LOCATOR64_BYTES || read_at(fd, loc, sizeof loc, end_at - LOCATOR64_BYTES) != 0 ||
        le32(loc) != SIG_LOCATOR64)
        return ORR_OK;
    uint64_t at = le64(loc + 8);
    if (at > end_at - LOCATOR64_BYTES || read_at(fd, rec, sizeof rec, at) != 0 || le32(rec) != SIG_END64)
        return orr_fail(err, ORR_ERR_FORMAT, "%s: the ZIP64 end record the locator names is not there", path);
    if (le32(rec + 16) != 0 || le32(rec + 20) != 0 || le32(loc + 16) > 1)
        return orr_fail(err, ORR_ERR_FORMAT, "%s: a ZIP archive on several disks (not read)", path);
    d->entries = le64(rec + 32);
    d->size = le64(rec + 40);
    d->offset = le64(rec + 48);
    if (d->offset > at || d->size > at - d->offset)
        return orr_fail(err, ORR_ERR_FORMAT, "%s: the ZIP64 end record puts the directory outside the file", path);
    return ORR_OK;
}

/* Finds the end of central directory record in the last 64 KiB of the
 * file (it is followed by a comment of up to 65535 bytes). */
static orr_status find_directory(int fd, const char *path, uint64_t file_size, directory_place *d, orr_error *err)
{
    size_t tail = file_size < END_BYTES + MAX_COMMENT ? (size_t)file_size : END_BYTES + MAX_COMMENT;
    unsigned char *buf = orr_malloc(tail ? tail : 1, "ZIP end record", err);
    if (!buf)
        return ORR_ERR_NOMEM;
    uint64_t base = file_size - tail;
    if (read_at(fd, buf, tail, base) != 0) {
        free(buf);
        return read_failed(path, "the ZIP end record", err);
    }
    long found = -1;
    for (long i = (long)tail - END_BYTES; i >= 0 && found < 0; i--)
        if (le32(buf + i) == SIG_END && (size_t)i + END_BYTES + le16(buf + i + 20) <= tail)
            found = i;
    orr_status s = ORR_OK;
    if (found < 0) {
        s = orr_fail(err, ORR_ERR_FORMAT, "%s: no ZIP end of central directory record (not an .npz archive, or "
                     "truncated)", path);
    } else if (le16(buf + found + 4) != 0 || le16(buf + found + 6) != 0) {
        s = orr_fail(err, ORR_ERR_FORMAT, "%s: a ZIP archive on several disks (not read)", path);
    } else {
        const unsigned char *e = buf + found;
        d->entries = le16(e + 10);
        d->size = le32(e + 12);
        d->offset = le32(e + 16);
        uint64_t end_at = base + (uint64_t)found;
        s = read_end64(fd, path, end_at, d, err);
        if (!s && (d->offset > end_at || d->size > end_at - d->offset))
            s = orr_fail(err, ORR_ERR_FORMAT, "%s: the ZIP end record puts the directory outside the file", path);
    }
    free(buf);
    return s;
}

/* The ZIP64 extra field (tag 1) of a directory entry: the 64-bit values of
 * the fields that hold 0xFFFFFFFF, in the order usize, csize, offset. */
static int apply_zip64_extra(const unsigned char *extra, size_t len, uint64_t *usize, uint64_t *csize,
                             uint64_t *offset)
{
    size_t at = 0;
    while (at + 4 <= len) {
        uint32_t tag = le16(extra + at), size = le16(extra + at + 2);
        if (at + 4 + size > len)
            return 0;
        if (tag == 1) {
            const unsigned char *v = extra + at + 4, *end = v + size;
            uint64_t *field[3] = {usize, csize, offset};
            for (int i = 0; i < 3; i++)
                if (*field[i] == 0xffffffffu) {
                    if (v + 8 > end)
                        return 0;
                    *field[i] = le64(v);
                    v += 8;
                }
            return 1;
        }
        at += 4 + size;
    }
    return !(*usize == 0xffffffffu || *csize == 0xffffffffu || *offset == 0xffffffffu);
}

/* Where a member's bytes start: after its local header's name and extra
 * field (whose lengths may differ from the directory's). */
static orr_status locate_data(int fd, const char *path, orr_zip_member *m, uint64_t header_at, uint64_t limit,
                              orr_error *err)
{
    unsigned char h[LOCAL_BYTES];
    if (header_at > limit || read_at(fd, h, sizeof h, header_at) != 0 || le32(h) != SIG_LOCAL)
        return orr_fail(err, ORR_ERR_FORMAT, "%s: member '%s': no local file header where the directory says", path,
                        m->name);
    uint64_t start = header_at + LOCAL_BYTES + le16(h + 26) + le16(h + 28);
    if (start > limit || m->csize > limit - start)
        return orr_fail(err, ORR_ERR_FORMAT, "%s: member '%s': its %" PRIu64 " bytes run past the directory "
                        "(truncated?)", path, m->name, m->csize);
    m->data_offset = (int64_t)start;
    return ORR_OK;
}

/* One directory entry at p (avail bytes left) into m; *used its length. */
static orr_status parse_entry(int fd, const char *path, const unsigned char *p, size_t avail, uint64_t limit,
                              orr_zip_member *m, size_t *used, orr_error *err)
{
    if (avail < CENTRAL_BYTES || le32(p) != SIG_CENTRAL)
        return orr_fail(err, ORR_ERR_FORMAT, "%s: a damaged ZIP central directory", path);
    size_t name_len = le16(p + 28), extra_len = le16(p + 30), comment_len = le16(p + 32);
    *used = CENTRAL_BYTES + name_len + extra_len + comment_len;
    if (*used > avail)
        return orr_fail(err, ORR_ERR_FORMAT, "%s: a damaged ZIP central directory", path);
    size_t keep = name_len < ORR_ZIP_NAME_MAX ? name_len : ORR_ZIP_NAME_MAX - 1;
    memcpy(m->name, p + CENTRAL_BYTES, keep);
    m->name[keep] = '\0';
    for (size_t i = 0; i < keep; i++)
        if ((unsigned char)m->name[i] < 0x20)
            m->name[i] = '?'; /* names go into messages */
    uint32_t flags = le16(p + 8);
    m->method = (int)le16(p + 10);
    m->crc = le32(p + 16);
    m->csize = le32(p + 20);
    m->usize = le32(p + 24);
    uint64_t header_at = le32(p + 42);
    if (!apply_zip64_extra(p + CENTRAL_BYTES + name_len, extra_len, &m->usize, &m->csize, &header_at))
        return orr_fail(err, ORR_ERR_FORMAT, "%s: member '%s': a damaged ZIP64 extra field", path, m->name);
    if (flags & 1)
        return orr_fail(err, ORR_ERR_FORMAT, "%s: member '%s' is encrypted", path, m->name);
    if (m->method != 0 && m->method != 8)
        return orr_fail(err, ORR_ERR_FORMAT, "%s: member '%s' is compressed with ZIP method %d: only stored (0) and "
                        "deflate (8), as numpy writes them, are read", path, m->name, m->method);
    if (m->method == 0 && m->csize != m->usize)
        return orr_fail(err, ORR_ERR_FORMAT, "%s: member '%s' is stored but its sizes differ (%" PRIu64 " and %" PRIu64
                        ")", path, m->name, m->csize, m->usize);
    return locate_data(fd, path, m, header_at, limit, err);
}

orr_status orr_zip_read_directory(int fd, const char *path, orr_zip_member **members, int *n, orr_error *err)
{
    *members = NULL;
    *n = 0;
    struct stat sb;
    if (fstat(fd, &sb) != 0)
        return orr_fail(err, ORR_ERR_IO, "%s: cannot stat: %s", path, strerror(errno));
    directory_place d = {0};
    orr_status s = find_directory(fd, path, (uint64_t)sb.st_size, &d, err);
    if (s)
        return s;
    if (d.entries > ORR_ZIP_MAX_MEMBERS || d.size > MAX_DIRECTORY)
        return orr_fail(err, ORR_ERR_FORMAT, "%s: a ZIP directory of %" PRIu64 " members in %" PRIu64 " bytes (at "
                        "most %d members are read)", path, d.entries, d.size, ORR_ZIP_MAX_MEMBERS);
    unsigned char *dir = orr_malloc(d.size ? (size_t)d.size : 1, "ZIP central directory", err);
    orr_zip_member *m = orr_calloc(d.entries ? (size_t)d.entries : 1, sizeof *m, "ZIP members", err);
    if (!dir || !m)
        s = ORR_ERR_NOMEM;
    else if (read_at(fd, dir, (size_t)d.size, d.offset) != 0)
        s = read_failed(path, "the ZIP central directory", err);
    size_t at = 0;
    for (uint64_t i = 0; !s && i < d.entries; i++) {
        size_t used = 0;
        s = parse_entry(fd, path, dir + at, (size_t)d.size - at, d.offset, &m[i], &used, err);
        at += used;
    }
    free(dir);
    if (s) {
        free(m);
        return s;
    }
    *members = m;
    *n = (int)d.entries;
    return ORR_OK;
}

/* ---- reading a member ---- */

static void end_inflate(orr_zip_reader *r)
{
    if (r->inflating)
        inflateEnd(&r->zs);
    r->inflating = 0;
}

/* Back to the member's first byte. */
static orr_status restart(orr_zip_reader *r, orr_error *err)
{
    end_inflate(r);
    r->pos = r->cpos = 0;
    r->crc = (uint32_t)crc32(0L, Z_NULL, 0);
    if (r->m->method != 8)
        return ORR_OK;
    memset(&r->zs, 0, sizeof r->zs);
    if (inflateInit2(&r->zs, -MAX_WBITS) != Z_OK) /* raw deflate: no zlib header in a ZIP */
        return orr_fail(err, ORR_ERR_NOMEM, "%s: cannot start inflating", r->what);
    r->inflating = 1;
    return ORR_OK;
}

orr_status orr_zip_reader_open(orr_zip_reader *r, int fd, const char *path, const orr_zip_member *m,
                               orr_error *err)
{
    memset(r, 0, sizeof *r);
    r->fd = fd;
    r->m = m;
    snprintf(r->what, sizeof r->what, "%s: member '%s'", path, m->name);
    if (m->method == 8 && !(r->in = orr_malloc(INFLATE_INPUT, "inflate input", err)))
        return ORR_ERR_NOMEM;
    return restart(r, err);
}

void orr_zip_reader_close(orr_zip_reader *r)
{
    end_inflate(r);
    free(r->in);
    r->in = NULL;
}

/* Inflates exactly n bytes into out. */
static orr_status inflate_bytes(orr_zip_reader *r, unsigned char *out, size_t n, orr_error *err)
{
    z_stream *zs = &r->zs;
    zs->next_out = out;
    while (n > 0) {
        zs->avail_out = n > 0x40000000u ? 0x40000000u : (uInt)n;
        if (zs->avail_in == 0 && r->cpos < r->m->csize) {
            size_t want = r->m->csize - r->cpos < INFLATE_INPUT ? (size_t)(r->m->csize - r->cpos) : INFLATE_INPUT;
            if (read_at(r->fd, r->in, want, (uint64_t)r->m->data_offset + r->cpos) != 0)
                return read_failed(r->what, "its compressed bytes", err);
            zs->next_in = r->in;
            zs->avail_in = (uInt)want;
            r->cpos += want;
        }
        uInt before = zs->avail_out;
        int z = inflate(zs, Z_NO_FLUSH);
        n -= before - zs->avail_out;
        if (n > 0 && (z == Z_STREAM_END || (z == Z_BUF_ERROR && zs->avail_in == 0 && r->cpos == r->m->csize)))
            return orr_fail(err, ORR_ERR_FORMAT, "%s: the deflated data ends before its %" PRIu64 " bytes", r->what,
                            r->m->usize);
        if (z != Z_OK && z != Z_STREAM_END && z != Z_BUF_ERROR)
            return orr_fail(err, ORR_ERR_FORMAT, "%s: damaged deflated data (%s)", r->what,
                            zs->msg ? zs->msg : "zlib error");
    }
    return ORR_OK;
}

orr_status orr_zip_read(orr_zip_reader *r, void *buf, size_t n, orr_error *err)
{
    if (n > r->m->usize - r->pos)
        return orr_fail(err, ORR_ERR_FORMAT, "%s: a read past its %" PRIu64 " bytes", r->what, r->m->usize);
    orr_status s = ORR_OK;
    if (r->m->method == 8)
        s = inflate_bytes(r, buf, n, err);
    else if (read_at(r->fd, buf, n, (uint64_t)r->m->data_offset + r->pos) != 0)
        s = read_failed(r->what, "its bytes", err);
    if (s)
        return s;
    /* zlib's crc32 takes at most 4 GiB a call. */
    for (size_t done = 0; done < n;) {
        uInt part = n - done > 0x40000000u ? 0x40000000u : (uInt)(n - done);
        r->crc = (uint32_t)crc32(r->crc, (const unsigned char *)buf + done, part);
        done += part;
    }
    r->pos += n;
    if (r->pos == r->m->usize && r->m->method == 8 && r->crc != r->m->crc)
        return orr_fail(err, ORR_ERR_FORMAT, "%s: CRC-32 %08" PRIx32 " of its data, but the archive says %08" PRIx32
                        " (a damaged file)", r->what, r->crc, r->m->crc);
    return ORR_OK;
}

orr_status orr_zip_seek(orr_zip_reader *r, uint64_t to, orr_error *err)
{
    if (to > r->m->usize)
        return orr_fail(err, ORR_ERR_FORMAT, "%s: a seek past its %" PRIu64 " bytes", r->what, r->m->usize);
    if (r->m->method != 8) {
        r->pos = to; /* stored bytes are read where they are; their CRC is not checked */
        return ORR_OK;
    }
    orr_status s = to < r->pos ? restart(r, err) : ORR_OK;
    unsigned char scratch[16384];
    while (!s && r->pos < to) {
        size_t k = to - r->pos < sizeof scratch ? (size_t)(to - r->pos) : sizeof scratch;
        s = orr_zip_read(r, scratch, k, err);
    }
    return s;
}
