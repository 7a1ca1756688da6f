/* One Gadget file's layout: byte order and SnapFormat from the first record
 * marker, the header, then a walk over every Fortran record (each framed by
 * two equal 4-byte length markers) that finds the blocks the reader uses and
 * checks each length against the file size and the particle counts. Only
 * small fixed-size reads happen here, so a file that lies about its sizes is
 * caught before the reader allocates anything for it. */
#include "source/readers/gadget_internal.h"

#include <errno.h>
#include <math.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/types.h>

#include "core/bytes.h"
#include "source/readers/mass_policy.h"
#include "source/source.h"

const char *const gadget_block_names[BLK_COUNT] = {"POS", "VEL", "ID", "MASS", "U", "RHO", "HSML", "POT"};

uint32_t gadget_u32(const unsigned char *p, int swap)
{
    return orr_load_u32(p, swap);
}

/* Decodes the Gadget-2 io_header layout (byte offsets from its start). */
static void decode_header(const unsigned char *b, int swap, gadget_header *h)
{
    for (int t = 0; t < GADGET_NTYPES; t++) {
        h->npart[t] = orr_load_i32(b + 4 * t, swap);
        h->massarr[t] = orr_load_f64(b + 24 + 8 * t, swap);
        h->npart_total[t] = gadget_u32(b + 96 + 4 * t, swap);
        h->npart_total_high[t] = gadget_u32(b + 168 + 4 * t, swap);
    }
    h->time = orr_load_f64(b + 72, swap);
    h->redshift = orr_load_f64(b + 80, swap);
    h->flag_sfr = orr_load_i32(b + 88, swap);
    h->flag_feedback = orr_load_i32(b + 92, swap);
    h->flag_cooling = orr_load_i32(b + 120, swap);
    h->num_files = orr_load_i32(b + 124, swap);
    h->box_size = orr_load_f64(b + 128, swap);
    h->omega0 = orr_load_f64(b + 136, swap);
    h->omega_lambda = orr_load_f64(b + 144, swap);
    h->hubble_param = orr_load_f64(b + 152, swap);
    h->flag_stellarage = orr_load_i32(b + 160, swap);
    h->flag_metals = orr_load_i32(b + 164, swap);
    h->flag_entropy = orr_load_i32(b + 192, swap);
}

typedef struct scan {
    FILE *fp;
    const char *path;
    int64_t size;
    int swap;
} scan;

/* Reads n bytes at offset, which must lie inside the file: what names the
 * record for the message when they do not. */
static orr_status read_at(scan *s, int64_t offset, void *buf, size_t n, const char *what, orr_error *err)
{
    if (offset < 0 || offset + (int64_t)n > s->size)
        return orr_fail(err, ORR_ERR_FORMAT,
                        "%s: %s: needs %zu bytes at offset %lld but the file ends at %lld (truncated file?)",
                        s->path, what, n, (long long)offset, (long long)s->size);
    if (fseeko(s->fp, (off_t)offset, SEEK_SET) != 0 || fread(buf, 1, n, s->fp) != n)
        return orr_fail(err, ORR_ERR_IO, "%s: %s: read error at offset %lld: %s", s->path, what,
                        (long long)offset, ferror(s->fp) ? strerror(errno) : "unexpected end of file");
    return ORR_OK;
}

static orr_status detect_encoding(scan *s, gadget_encoding *enc, orr_error *err)
{
    unsigned char b[4];
    if (s->size < 4)
        return orr_fail(err, ORR_ERR_FORMAT, "%s: %lld bytes is too short for a Gadget snapshot", s->path,
                        (long long)s->size);
    orr_status st = read_at(s, 0, b, 4, "first record marker", err);
    if (st)
        return st;
    int host_big = orr_host_big_endian();
    uint32_t native = gadget_u32(b, 0), swapped = gadget_u32(b, 1);
    gadget_encoding found = {1, 0, host_big, 0};
    if (native == 256 || native == 8) {
        found.snapformat = native == 8 ? 2 : 1;
    } else if (swapped == 256 || swapped == 8) {
        found.swap = 1;
        found.big_endian = !host_big;
        found.snapformat = swapped == 8 ? 2 : 1;
    } else {
        return orr_fail(err, ORR_ERR_FORMAT,
                        "%s: first record marker is %u read little endian and %u read big endian; a Gadget "
                        "snapshot starts with 256 (SnapFormat 1) or 8 (SnapFormat 2) in one byte order "
                        "(not a Gadget file, or a damaged one)",
                        s->path, host_big ? swapped : native, host_big ? native : swapped);
    }
    if (enc->known && (found.swap != enc->swap || found.snapformat != enc->snapformat))
        return orr_fail(err, ORR_ERR_FORMAT,
                        "%s: SnapFormat %d %s endian, but the snapshot's first file is SnapFormat %d %s endian",
                        s->path, found.snapformat, found.big_endian ? "big" : "little", enc->snapformat,
                        enc->big_endian ? "big" : "little");
    *enc = found;
    s->swap = found.swap;
    return ORR_OK;
}

/* Reads a record's opening marker at offset and checks that the record fits
 * in the file and that its closing marker repeats it. */
static orr_status read_record(scan *s, int64_t offset, const char *name, uint32_t *bytes, orr_error *err)
{
    unsigned char b[4];
    char what[64];
    snprintf(what, sizeof what, "block %s: record marker", name);
    orr_status st = read_at(s, offset, b, 4, what, err);
    if (st)
        return st;
    uint32_t m = gadget_u32(b, s->swap);
    int64_t end = offset + 4 + (int64_t)m + 4;
    if (end > s->size)
        return orr_fail(err, ORR_ERR_FORMAT,
                        "%s: block %s: record marker at offset %lld says %u bytes, but the record would end at "
                        "offset %lld, past the end of the file (size %lld): truncated file or a wrong marker",
                        s->path, name, (long long)offset, m, (long long)end, (long long)s->size);
    snprintf(what, sizeof what, "block %s: closing record marker", name);
    if ((st = read_at(s, end - 4, b, 4, what, err)))
        return st;
    uint32_t closing = gadget_u32(b, s->swap);
    if (closing != m)
        return orr_fail(err, ORR_ERR_FORMAT,
                        "%s: block %s: opening record marker says %u bytes, the closing marker at offset %lld says %u",
                        s->path, name, m, (long long)(end - 4), closing);
    *bytes = m;
    return ORR_OK;
}

/* SnapFormat 2: the 8-byte record before each block, label[4] + the next
 * record's length (data + 8 marker bytes). */
static orr_status read_label(scan *s, int64_t offset, char label[5], uint32_t *next, orr_error *err)
{
    unsigned char b[16];
    orr_status st = read_at(s, offset, b, sizeof b, "block label record", err);
    if (st)
        return st;
    uint32_t m1 = gadget_u32(b, s->swap), m2 = gadget_u32(b + 12, s->swap);
    if (m1 != 8 || m2 != 8)
        return orr_fail(err, ORR_ERR_FORMAT,
                        "%s: block label record at offset %lld: markers %u and %u, expected 8 and 8 (SnapFormat 2)",
                        s->path, (long long)offset, m1, m2);
    int len = 4;
    while (len > 0 && (b[3 + len] == ' ' || b[3 + len] == '\0'))
        len--;
    for (int i = 0; i < len; i++)
        label[i] = (b[4 + i] >= 0x20 && b[4 + i] < 0x7f) ? (char)b[4 + i] : '?';
    label[len] = '\0';
    *next = gadget_u32(b + 8, s->swap);
    return ORR_OK;
}

static orr_status read_header(scan *s, const gadget_encoding *enc, gadget_header *h, int64_t *end,
                              orr_error *err)
{
    int64_t offset = 0;
    if (enc->snapformat == 2) {
        char label[5];
        uint32_t next;
        orr_status st = read_label(s, 0, label, &next, err);
        if (st)
            return st;
        if (strcmp(label, "HEAD") != 0)
            return orr_fail(err, ORR_ERR_FORMAT, "%s: first block label is '%s', expected 'HEAD' (SnapFormat 2)",
                            s->path, label);
        offset = 16;
    }
    unsigned char b[4 + GADGET_HEADER_BYTES + 4];
    orr_status st = read_at(s, offset, b, sizeof b, "header record", err);
    if (st)
        return st;
    uint32_t m1 = gadget_u32(b, s->swap), m2 = gadget_u32(b + 4 + GADGET_HEADER_BYTES, s->swap);
    if (m1 != GADGET_HEADER_BYTES || m2 != GADGET_HEADER_BYTES)
        return orr_fail(err, ORR_ERR_FORMAT, "%s: block HEAD: record markers %u and %u, expected %d and %d",
                        s->path, m1, m2, GADGET_HEADER_BYTES, GADGET_HEADER_BYTES);
    decode_header(b + 4, s->swap, h);
    for (int t = 0; t < GADGET_NTYPES; t++)
        if (h->npart[t] < 0)
            return orr_fail(err, ORR_ERR_FORMAT, "%s: header npart[%d] = %d is negative", s->path, t,
                            (int)h->npart[t]);
    if (h->num_files < 0)
        return orr_fail(err, ORR_ERR_FORMAT, "%s: header num_files = %d is negative", s->path, (int)h->num_files);
    /* The time goes into every image's FITS header (and orders a sequence's
     * snapshots): a NaN or infinity there fails every render at its end. */
    if (!isfinite(h->time))
        return orr_fail(err, ORR_ERR_FORMAT, "%s: header time = %g is not a finite number", s->path, h->time);
    *end = offset + (int64_t)sizeof b;
    return ORR_OK;
}

static gadget_block_kind kind_of_label(const char *label)
{
    static const char *const labels[BLK_COUNT] = {"POS", "VEL", "ID", "MASS", "U", "RHO", "HSML", "POT"};
    for (int k = 0; k < BLK_COUNT; k++)
        if (strcmp(label, labels[k]) == 0)
            return (gadget_block_kind)k;
    return BLK_COUNT;
}

/* SnapFormat 1 has no labels: blocks are known by their place in Gadget-2's
 * output order (POS VEL ID [MASS] then gas blocks U RHO [NE NH] HSML ...).
 * Gas blocks are taken only when their length fits the gas count, so files
 * with other blocks after MASS are still read (without those fields). */
typedef struct positional {
    int next;      /* records seen after the header */
    int gas_seen;  /* gas-sized records seen after POS VEL ID [MASS] */
    int gas_done;  /* a record that is not gas-sized ended the gas blocks */
} positional;

static gadget_block_kind kind_by_position(positional *p, const gadget_file *f, int64_t nvar, uint32_t bytes)
{
    int r = p->next++;
    if (r < 3)
        return (gadget_block_kind)(BLK_POS + r);
    /* MASS comes next when some type needs it; an empty record there is an
     * empty MASS block of a part with none of those particles. */
    if (r == 3 && (nvar > 0 || bytes == 0))
        return BLK_MASS;
    int64_t ngas = f->h.npart[0];
    if (p->gas_done || ngas == 0 || (bytes != ngas * 4 && bytes != ngas * 8)) {
        p->gas_done = 1;
        return BLK_COUNT;
    }
    int g = p->gas_seen++;
    if (g == 0)
        return BLK_U;
    if (g == 1)
        return BLK_RHO;
    if (g == (f->h.flag_cooling ? 4 : 2)) /* NE and NH come before HSML when cooling is on */
        return BLK_HSML;
    return BLK_COUNT;
}

/* Notes where a SnapFormat 2 block with another label is (beyond
 * GADGET_MAX_NAMED of them, the rest are stepped over). */
static orr_status note_named(const char *path, gadget_file *f, const char *label, int64_t offset, uint32_t bytes,
                             orr_error *err)
{
    if (!label[0] || strcmp(label, "HEAD") == 0)
        return ORR_OK; /* a blank label names nothing; a second header is no field */
    if (gadget_named_find(f, label))
        return orr_fail(err, ORR_ERR_FORMAT, "%s: block %s appears twice", path, label);
    if (f->nnamed == GADGET_MAX_NAMED)
        return ORR_OK;
    gadget_named_block *b = &f->named[f->nnamed++];
    snprintf(b->label, sizeof b->label, "%s", label);
    b->offset = offset + 4;
    b->bytes = bytes;
    return ORR_OK;
}

/* Walks every record after the header and notes where the known blocks are. */
static orr_status walk_records(scan *s, const gadget_encoding *enc, int64_t offset, int64_t nvar,
                               gadget_file *f, orr_error *err)
{
    positional pos = {0, 0, 0};
    int index = 0;
    while (offset < s->size) {
        char label[5] = "", name[32];
        uint32_t next = 0, bytes = 0;
        orr_status st;
        if (enc->snapformat == 2) {
            if ((st = read_label(s, offset, label, &next, err)))
                return st;
            offset += 16;
            snprintf(name, sizeof name, "%s", label);
        } else {
            snprintf(name, sizeof name, "#%d after the header", index + 1);
        }
        if ((st = read_record(s, offset, name, &bytes, err)))
            return st;
        if (enc->snapformat == 2 && next != bytes + 8 && next != bytes)
            return orr_fail(err, ORR_ERR_FORMAT,
                            "%s: block %s: the label record announces %u bytes, the data record holds %u (+8 markers)",
                            s->path, name, next, bytes);
        gadget_block_kind k = enc->snapformat == 2 ? kind_of_label(label) : kind_by_position(&pos, f, nvar, bytes);
        if (k == BLK_COUNT && enc->snapformat == 2 && (st = note_named(s->path, f, label, offset, bytes, err)))
            return st;
        if (k != BLK_COUNT) {
            if (f->blk[k].present)
                return orr_fail(err, ORR_ERR_FORMAT, "%s: block %s appears twice", s->path, gadget_block_names[k]);
            f->blk[k] = (gadget_block){1, offset + 4, bytes, 4};
        }
        offset += 8 + (int64_t)bytes;
        index++;
    }
    return ORR_OK;
}

/* Sets the block's element size from its length: count values of ncomp
 * components, as float/int32 or double/int64. */
static orr_status check_block(const char *path, gadget_block *b, gadget_block_kind k, int64_t count, int ncomp,
                              const char *counted, orr_error *err)
{
    if (!b->present)
        return ORR_OK;
    int64_t values = count * ncomp;
    if (values > 0 && b->bytes == values * 4)
        b->elem = 4;
    else if (values > 0 && b->bytes == values * 8)
        b->elem = 8;
    else if (values > 0 || b->bytes != 0)
        return orr_fail(err, ORR_ERR_FORMAT,
                        "%s: block %s holds %lld bytes; %lld %s need %lld (%s) or %lld (%s)", path,
                        gadget_block_names[k], (long long)b->bytes, (long long)count, counted,
                        (long long)(values * 4), k == BLK_ID ? "32-bit ids" : "float",
                        (long long)(values * 8), k == BLK_ID ? "64-bit ids" : "double");
    return ORR_OK;
}

/* Names the types whose masses come from the MASS block, e.g. "0 4". */
static void variable_mass_types(const gadget_header *h, char *buf, size_t size)
{
    buf[0] = '\0';
    for (int t = 0; t < GADGET_NTYPES; t++)
        if (h->npart[t] > 0 && h->massarr[t] == 0) {
            size_t len = strlen(buf);
            snprintf(buf + len, size - len, "%s%d", len ? " " : "", t);
        }
}

/* A type's massarr is every one of its particles' mass: the same policy as
 * masses read from a MASS block (types without particles here are unused). */
static orr_status check_mass_table(const char *path, const gadget_header *h, orr_error *err)
{
    for (int t = 0; t < GADGET_NTYPES; t++) {
        const char *problem = h->npart[t] > 0 && h->massarr[t] != 0 ? orr_mass_problem(h->massarr[t]) : NULL;
        if (problem)
            return orr_fail(err, ORR_ERR_FORMAT, "%s: header massarr[%d] = %g %s (the mass of its %d particles)",
                            path, t, h->massarr[t], problem, (int)h->npart[t]);
    }
    return ORR_OK;
}

static orr_status check_blocks(const char *path, gadget_file *f, int64_t nvar, orr_error *err)
{
    int64_t ngas = f->h.npart[0];
    if (f->n > 0 && !f->blk[BLK_POS].present)
        return orr_fail(err, ORR_ERR_FORMAT, "%s: no POS block, but the header counts %lld particles", path,
                        (long long)f->n);
    if (nvar > 0 && !f->blk[BLK_MASS].present) {
        char types[32];
        variable_mass_types(&f->h, types, sizeof types);
        return orr_fail(err, ORR_ERR_FORMAT,
                        "%s: types %s have massarr 0, so their %lld masses must be in a MASS block, but there is none",
                        path, types, (long long)nvar);
    }
    orr_status st;
    if ((st = check_block(path, &f->blk[BLK_POS], BLK_POS, f->n, 3, "particles", err)) ||
        (st = check_block(path, &f->blk[BLK_VEL], BLK_VEL, f->n, 3, "particles", err)) ||
        (st = check_block(path, &f->blk[BLK_ID], BLK_ID, f->n, 1, "particles", err)) ||
        (st = check_block(path, &f->blk[BLK_MASS], BLK_MASS, nvar, 1, "particles of types with massarr 0", err)) ||
        (st = check_block(path, &f->blk[BLK_U], BLK_U, ngas, 1, "gas particles", err)) ||
        (st = check_block(path, &f->blk[BLK_RHO], BLK_RHO, ngas, 1, "gas particles", err)) ||
        (st = check_block(path, &f->blk[BLK_HSML], BLK_HSML, ngas, 1, "gas particles", err)) ||
        (st = check_block(path, &f->blk[BLK_POT], BLK_POT, f->n, 1, "particles", err)))
        return st;
    return check_mass_table(path, &f->h, err);
}

/* Particle counts and where each type starts in the particle and MASS blocks. */
static int64_t count_particles(gadget_file *f)
{
    int64_t nvar = 0;
    f->n = 0;
    for (int t = 0; t < GADGET_NTYPES; t++) {
        f->type_start[t] = f->n;
        f->mass_start[t] = nvar;
        f->n += f->h.npart[t];
        if (f->h.massarr[t] == 0)
            nvar += f->h.npart[t];
    }
    return nvar;
}

static orr_status scan_open(scan *s, const char *path, orr_error *err)
{
    s->path = path;
    orr_status st = orr_source_refuse_stream(path, "gadget", err);
    if (st)
        return st;
    s->fp = fopen(path, "rb");
    if (!s->fp)
        return orr_fail(err, ORR_ERR_IO, "%s: cannot open: %s", path, strerror(errno));
    struct stat sb;
    if (fstat(fileno(s->fp), &sb) != 0)
        return orr_fail(err, ORR_ERR_IO, "%s: cannot stat: %s", path, strerror(errno));
    if (!S_ISREG(sb.st_mode))
        return orr_fail(err, ORR_ERR_IO, "%s: not a regular file", path);
    s->size = (int64_t)sb.st_size;
    return ORR_OK;
}

orr_status gadget_scan_file(const char *path, gadget_encoding *enc, gadget_file *f, orr_error *err)
{
    memset(f, 0, sizeof *f);
    scan s = {0};
    int64_t offset = 0;
    orr_status st = scan_open(&s, path, err);
    if (!st)
        st = detect_encoding(&s, enc, err);
    if (!st)
        st = read_header(&s, enc, &f->h, &offset, err);
    if (!st) {
        f->size = s.size;
        int64_t nvar = count_particles(f);
        st = walk_records(&s, enc, offset, nvar, f, err);
        if (!st)
            st = check_blocks(path, f, nvar, err);
    }
    if (s.fp)
        fclose(s.fp);
    return st;
}
