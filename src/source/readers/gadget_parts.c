/* The parts of a Gadget snapshot, found and checked one by one, and what
 * `orrery info` shows of them (gadget_internal.h). */
#include "source/readers/gadget_internal.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/types.h>

/* Per-file npart lines shown by `orrery info` for multi-file snapshots. */
#define GADGET_INFO_FILES 8

void gadget_part_path(const gadget_state *st, int i, char *buf, size_t size)
{
    if (st->multi)
        snprintf(buf, size, "%s.%d", st->base, i);
    else
        snprintf(buf, size, "%s", st->base);
}

/* ---- finding the parts ---- */

static int file_exists(const char *path)
{
    struct stat sb;
    return stat(path, &sb) == 0;
}

/* The part number when path ends in ".<digits>", else -1. */
static long part_suffix(const char *path, size_t *stem_len)
{
    const char *dot = strrchr(path, '.');
    if (!dot || !dot[1] || strchr(dot, '/') || strlen(dot + 1) > 9)
        return -1;
    for (const char *p = dot + 1; *p; p++)
        if (*p < '0' || *p > '9')
            return -1;
    *stem_len = (size_t)(dot - path);
    return strtol(dot + 1, NULL, 10);
}

/* Appends one more part to st->files, growing the array as parts are found
 * (a header's num_files is not trusted for an allocation). */
static orr_status add_part(gadget_state *st, const gadget_file *f, int *cap, orr_error *err)
{
    if (st->nfiles == *cap) {
        int grown = *cap ? 2 * *cap : 4;
        gadget_file *files = realloc(st->files, (size_t)grown * sizeof *files);
        if (!files)
            return orr_fail(err, ORR_ERR_NOMEM, "out of memory for %d snapshot parts", grown);
        st->files = files;
        *cap = grown;
    }
    st->files[st->nfiles++] = *f;
    return ORR_OK;
}

static orr_status scan_parts(gadget_state *st, int nparts, int num_files, orr_error *err)
{
    int cap = 0;
    for (int i = 0; i < nparts; i++) {
        char path[ORR_PATH_MAX + 16];
        gadget_part_path(st, i, path, sizeof path);
        gadget_file f;
        orr_status s = gadget_scan_file(path, &st->enc, &f, err);
        if (s) {
            orr_fail_prefix(err, "snapshot %s, part %d of %d: ", st->base, i, nparts);
            return s;
        }
        if (f.h.num_files != num_files)
            return orr_fail(err, ORR_ERR_FORMAT, "%s: header num_files = %d, but part 0 says %d", path,
                            (int)f.h.num_files, num_files);
        if ((s = add_part(st, &f, &cap, err)))
            return s;
    }
    return ORR_OK;
}

/* Reads the file path names (or path.0) and, for a multi-file snapshot,
 * every other part. */
orr_status gadget_find_parts(const char *path, gadget_state *st, orr_error *err)
{
    if (strlen(path) >= ORR_PATH_MAX - 16)
        return orr_fail(err, ORR_ERR_IO, "%.64s...: path too long", path);
    int base_given = !file_exists(path);
    char first[ORR_PATH_MAX + 16];
    snprintf(first, sizeof first, base_given ? "%s.0" : "%s", path);
    if (base_given && !file_exists(first))
        return orr_fail(err, ORR_ERR_IO, "%s: cannot open: %s (nor is there a %s.0)", path, strerror(ENOENT),
                        path);
    gadget_file f;
    orr_status s = gadget_scan_file(first, &st->enc, &f, err);
    if (s)
        return s;
    int num_files = f.h.num_files;
    snprintf(st->base, sizeof st->base, "%s", path);
    if (num_files <= 1) { /* 0 in old IC files means a single file too */
        snprintf(st->base, sizeof st->base, base_given ? "%s.0" : "%s", path);
        int cap = 0;
        return add_part(st, &f, &cap, err);
    }
    size_t stem = 0;
    long part = base_given ? 0 : part_suffix(path, &stem);
    if (part < 0)
        return orr_fail(err, ORR_ERR_FORMAT,
                        "%s: header num_files = %d, but the name does not end in .0, .1, ...: cannot find the "
                        "other parts (name the snapshot as snap or snap.0)",
                        path, num_files);
    if (part >= num_files)
        return orr_fail(err, ORR_ERR_FORMAT, "%s: part %ld of a snapshot whose header says num_files = %d", path,
                        part, num_files);
    if (!base_given)
        st->base[stem] = '\0';
    st->multi = 1;
    st->enc.known = 0; /* part 0 decides */
    return scan_parts(st, num_files, num_files, err);
}

/* ---- info ---- */

static void add_int6(orr_source_info *info, const char *key, const int64_t v[GADGET_NTYPES])
{
    orr_source_add_header(info, key, "%lld %lld %lld %lld %lld %lld", (long long)v[0], (long long)v[1],
                          (long long)v[2], (long long)v[3], (long long)v[4], (long long)v[5]);
}

static void add_npart(orr_source_info *info, const char *key, const int32_t n[GADGET_NTYPES])
{
    int64_t v[GADGET_NTYPES];
    for (int t = 0; t < GADGET_NTYPES; t++)
        v[t] = n[t];
    add_int6(info, key, v);
}

/* Checks npartTotal (+ HighWord) against the parts' npart, which are what
 * is read (they were checked against the block lengths). Old writers leave
 * npartTotal zero or the high word full of junk: both give a note, not an
 * error. */
static void check_totals(orr_source_info *info, const gadget_state *st, const int64_t sum[GADGET_NTYPES])
{
    const gadget_header *h = &st->files[0].h;
    int any_total = 0, any_high = 0;
    int64_t low[GADGET_NTYPES], high[GADGET_NTYPES];
    for (int t = 0; t < GADGET_NTYPES; t++) {
        low[t] = h->npart_total[t];
        high[t] = h->npart_total_high[t];
        any_total |= low[t] != 0 || high[t] != 0;
        any_high |= high[t] != 0;
    }
    add_int6(info, "npartTotal", low);
    if (any_high)
        add_int6(info, "npartTotalHighWord", high);
    if (!any_total) {
        orr_source_add_header(info, "note", "npartTotal is all 0 (not filled in): using the files' npart");
        return;
    }
    for (int t = 0; t < GADGET_NTYPES; t++) {
        int64_t full = low[t] + (int64_t)((uint64_t)high[t] << 32);
        if (full == sum[t])
            continue;
        if (high[t] != 0 && low[t] == sum[t])
            orr_source_add_header(info, "warning",
                                  "npartTotalHighWord[%d] = %lld ignored: the files hold %lld type-%d particles", t,
                                  (long long)high[t], (long long)sum[t], t);
        else
            orr_source_add_header(info, "warning",
                                  "npartTotal[%d] = %lld, but the files hold %lld type-%d particles: using the files",
                                  t, (long long)full, (long long)sum[t], t);
    }
}

/* The shortest "%g" text that reads back as v (0.71, not 0.70999999999999996). */
static const char *shortest(char buf[32], double v)
{
    for (int digits = 6; digits < 17; digits++) {
        snprintf(buf, 32, "%.*g", digits, v);
        if (strtod(buf, NULL) == v)
            return buf;
    }
    snprintf(buf, 32, "%.17g", v);
    return buf;
}

static void add_real(orr_source_info *info, const char *key, double v)
{
    char buf[32];
    orr_source_add_header(info, key, "%s", shortest(buf, v));
}

/* One header line per named block: the particles it covers and the field
 * names it gives ("AGE  types 4, 1 float each: field AGE"), or why its
 * layout cannot be told. */
static void describe_named(orr_source_info *info, const gadget_state *st)
{
    char seen[GADGET_MAX_NAMED * 2][5];
    int nseen = 0;
    for (int i = 0; i < st->nfiles; i++)
        for (int b = 0; b < st->files[i].nnamed && nseen < GADGET_MAX_NAMED * 2; b++) {
            const char *label = st->files[i].named[b].label;
            int dup = 0;
            for (int j = 0; j < nseen && !dup; j++)
                dup = strcmp(seen[j], label) == 0;
            if (dup)
                continue;
            snprintf(seen[nseen++], sizeof seen[0], "%s", label);
            gadget_named_layout l;
            gadget_named_infer(st->files, st->nfiles, label, &l);
            char types[24];
            gadget_type_list(l.types, types, sizeof types);
            const char *precision = l.elem == 8 ? "double" : "float";
            if (!l.ok)
                orr_source_add_header(info, label, "%s", l.why);
            else if (l.ncomp == 1)
                orr_source_add_header(info, label, "%s, 1 %s each: field %s", types, precision, label);
            else
                orr_source_add_header(info, label, "%s, %d %ss each: fields %s[0..%d]", types, l.ncomp, precision,
                                      label, l.ncomp - 1);
        }
}

void gadget_describe(orr_source *src, const gadget_state *st, const int64_t sum[GADGET_NTYPES])
{
    orr_source_info *info = &src->info;
    const gadget_header *h = &st->files[0].h;
    orr_source_add_header(info, "SnapFormat", "%d", st->enc.snapformat);
    orr_source_add_header(info, "byte order", "%s endian", st->enc.big_endian ? "big" : "little");
    orr_source_add_header(info, "num_files", "%d%s", (int)h->num_files,
                          h->num_files == 0 ? " (read as a single file)" : "");
    for (int i = 0; i < st->nfiles && i < GADGET_INFO_FILES; i++) {
        char key[48];
        snprintf(key, sizeof key, st->multi ? "npart (file %d)" : "npart", i);
        add_npart(info, key, st->files[i].h.npart);
    }
    if (st->nfiles > GADGET_INFO_FILES)
        orr_source_add_header(info, "npart (other files)", "%d more files not shown",
                              st->nfiles - GADGET_INFO_FILES);
    add_int6(info, "particles per type", sum);
    check_totals(info, st, sum);
    char m[GADGET_NTYPES][32];
    orr_source_add_header(info, "massarr", "%s %s %s %s %s %s", shortest(m[0], h->massarr[0]),
                          shortest(m[1], h->massarr[1]), shortest(m[2], h->massarr[2]),
                          shortest(m[3], h->massarr[3]), shortest(m[4], h->massarr[4]),
                          shortest(m[5], h->massarr[5]));
    add_real(info, "time", h->time);
    add_real(info, "redshift", h->redshift);
    add_real(info, "BoxSize", h->box_size);
    add_real(info, "Omega0", h->omega0);
    add_real(info, "OmegaLambda", h->omega_lambda);
    add_real(info, "HubbleParam", h->hubble_param);
    orr_source_add_header(info, "flags", "sfr=%d feedback=%d cooling=%d stellarage=%d metals=%d entropy_instead_u=%d",
                          (int)h->flag_sfr, (int)h->flag_feedback, (int)h->flag_cooling, (int)h->flag_stellarage,
                          (int)h->flag_metals, (int)h->flag_entropy);
    const gadget_file *f0 = &st->files[0];
    orr_source_add_header(info, "id width", "%s",
                          !st->has_id ? "none (no ID block: particles numbered from 0)"
                          : f0->blk[BLK_ID].elem == 8 ? "64-bit" : "32-bit");
    orr_source_add_header(info, "precision", "%s", f0->blk[BLK_POS].elem == 8 ? "double" : "float");
    char blocks[96] = "";
    for (int k = 0; k < BLK_COUNT; k++)
        if (f0->blk[k].present) {
            size_t len = strlen(blocks);
            snprintf(blocks + len, sizeof blocks - len, "%s%s", len ? " " : "", gadget_block_names[k]);
        }
    orr_source_add_header(info, "blocks read", "%s", blocks);
    describe_named(info, st);
}

/* How many values of block k a part would hold: gas blocks have one per gas
 * particle; MASS one per particle of the types whose massarr is 0 (GADGET-2
 * writes no MASS block into a part without such particles); the rest one
 * per particle. */
