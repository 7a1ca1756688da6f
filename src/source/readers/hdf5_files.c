/* The HDF5 snapshot reader's files (hdf5_internal.h): a snapshot's files
 * found, and every header, group and dataset shape checked before reading,
 * so absurd particle counts are caught before anything is allocated. */
#include "source/readers/hdf5_internal.h"

#include <errno.h>
#include <inttypes.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "source/readers/hdf5_reader.h"
#include "source/readers/mass_policy.h"

/* More files than this is not a snapshot but a corrupt header. */
#define H5R_MAX_FILES 100000
/* HDF5 reads whole chunks: a dataset whose chunks are larger than this would
 * need that much memory for any read, however small. */
#define H5R_MAX_HDF5_CHUNK_BYTES ((uint64_t)256 << 20)
/* No filter HDF5 ships compresses real particle data by more than this (deflate
 * tops out near 1032:1); a larger ratio means rows that were never written,
 * which would be read as fill values for as long as the claimed count says. */
#define H5R_MAX_COMPRESSION 1100

/* ---- Finding the files ---------------------------------------------- */

/* stat(), not fopen(): opening a FIFO would wait for a writer. */
static int file_exists(const char *path)
{
    struct stat sb;
    return stat(path, &sb) == 0;
}

/* Splits "dir/snap.12.hdf5" into base "dir/snap" and ext ".hdf5"; returns 1
 * when the name has that form (a number between the last two dots). */
static int split_numbered(const char *path, char *base, size_t bsize, char *ext, size_t esize)
{
    const char *dot = strrchr(path, '.');
    if (!dot || strchr(dot, '/') || strlen(dot) >= esize)
        return 0;
    const char *p = dot;
    while (p > path && p[-1] >= '0' && p[-1] <= '9')
        p--;
    if (p == dot || p == path || p[-1] != '.' || (size_t)(p - 1 - path) >= bsize || p - 1 == path)
        return 0;
    snprintf(base, bsize, "%.*s", (int)(p - 1 - path), path);
    snprintf(ext, esize, "%s", dot);
    return 1;
}

void h5r_file_name(const hdf5_state *st, int i, char *buf, size_t size)
{
    if (st->numbered && st->nfiles > 1)
        snprintf(buf, size, "%s.%d%s", st->base, i, st->ext);
    else
        snprintf(buf, size, "%s", st->first);
}

/* Decides which file to open first: path itself when it exists, else the
 * first file of a multi-file snapshot whose base path names. */
orr_status h5r_resolve_first_file(hdf5_state *st, const char *path, orr_error *err)
{
    if (strlen(path) >= sizeof st->base)
        return orr_fail(err, ORR_ERR_USAGE, "%.200s...: file name too long", path);
    if (file_exists(path)) {
        snprintf(st->first, sizeof st->first, "%s", path);
        st->numbered = split_numbered(path, st->base, sizeof st->base, st->ext, sizeof st->ext);
        return ORR_OK;
    }
    int saved = errno;
    size_t len = strlen(path);
    static const char *const exts[] = {".hdf5", ".h5"};
    snprintf(st->base, sizeof st->base, "%s", path);
    snprintf(st->ext, sizeof st->ext, ".hdf5");
    for (size_t i = 0; i < sizeof exts / sizeof exts[0]; i++) {
        size_t el = strlen(exts[i]);
        if (len > el && strcmp(path + len - el, exts[i]) == 0) {
            st->base[len - el] = '\0';
            snprintf(st->ext, sizeof st->ext, "%s", exts[i]);
        }
    }
    snprintf(st->first, sizeof st->first, "%s.0%s", st->base, st->ext);
    if (!file_exists(st->first))
        return orr_fail(err, ORR_ERR_IO, "%s: cannot open: %s (nor is there a multi-file snapshot %s)", path,
                        strerror(saved), st->first);
    st->numbered = 1;
    return ORR_OK;
}

/* Opens one file read-only, telling apart missing files, files that are not
 * HDF5 and HDF5 files the library cannot read (truncated, corrupt). */
orr_status h5r_open_file(const char *path, hid_t *fid, const char *context, orr_error *err)
{
    unsigned char head[4096];
    orr_status s = orr_source_refuse_stream(path, "hdf5", err);
    if (s)
        return s;
    FILE *fp = fopen(path, "rb");
    if (!fp)
        return orr_fail(err, ORR_ERR_IO, "%s: cannot open: %s%s", path, strerror(errno), context);
    size_t n = fread(head, 1, sizeof head, fp);
    fclose(fp);
    if (!orr_hdf5_probe(head, n))
        return orr_fail(err, ORR_ERR_FORMAT, "%s: not an HDF5 file (no HDF5 signature at byte 0, 512, 1024 or 2048)%s",
                        path, context);
    orr_h5_quiet();
    *fid = H5Fopen(path, H5F_ACC_RDONLY, H5P_DEFAULT);
    if (*fid < 0) {
        char why[256];
        orr_h5_reason(why, sizeof why);
        return orr_fail(err, ORR_ERR_FORMAT, "%s: HDF5 cannot open it (%s): truncated or corrupt?%s", path,
                        why[0] ? why : "no reason given", context);
    }
    return ORR_OK;
}

/* ---- Header --------------------------------------------------------- */

/* Reads a numeric Header attribute; absent is an error only when required. */
static orr_status header_numbers(const char *path, hid_t header, const char *name, hid_t memtype, void *out,
                                 int max, int required, int *count, orr_error *err)
{
    char why[256];
    switch (orr_h5_attr_numbers(header, name, memtype, out, max, count)) {
    case ORR_H5_FOUND: return ORR_OK;
    case ORR_H5_ABSENT:
        if (!required)
            return ORR_OK;
        return orr_fail(err, ORR_ERR_FORMAT, "%s: Header has no %s attribute", path, name);
    case ORR_H5_WRONG_TYPE:
        return orr_fail(err, ORR_ERR_FORMAT, "%s: Header/%s is not a list of numbers", path, name);
    case ORR_H5_TOO_MANY:
        return orr_fail(err, ORR_ERR_FORMAT, "%s: Header/%s has %d entries; expected at most %d", path, name,
                        *count, max);
    case ORR_H5_UNREADABLE: break;
    }
    orr_h5_reason(why, sizeof why);
    return orr_fail(err, ORR_ERR_FORMAT, "%s: Header/%s cannot be read (%s)", path, name, why);
}

orr_status h5r_open_header(const char *path, hid_t fid, hid_t *header, orr_error *err)
{
    if (!orr_h5_has_link(fid, "Header"))
        return orr_fail(err, ORR_ERR_FORMAT,
                        "%s: no Header group: not a Gadget/GIZMO/AREPO/SWIFT snapshot (expected Header and PartType0..N groups)",
                        path);
    *header = H5Gopen2(fid, "Header", H5P_DEFAULT);
    if (*header < 0) {
        char why[256];
        orr_h5_reason(why, sizeof why);
        return orr_fail(err, ORR_ERR_FORMAT, "%s: Header is not a readable group (%s)", path, why);
    }
    return ORR_OK;
}

/* Reads NumPart_ThisFile into counts; sets *ntypes from its length. */
static orr_status read_counts(const char *path, hid_t header, int64_t *counts, int *ntypes, orr_error *err)
{
    orr_status s = header_numbers(path, header, "NumPart_ThisFile", H5T_NATIVE_INT64, counts, H5R_MAX_TYPES, 1,
                                  ntypes, err);
    if (s)
        return s;
    for (int t = 0; t < *ntypes; t++)
        if (counts[t] < 0)
            return orr_fail(err, ORR_ERR_FORMAT, "%s: Header/NumPart_ThisFile[%d] = %" PRId64 " is negative", path,
                            t, counts[t]);
    return ORR_OK;
}

/* The first file's header: the type count, mass table and file count. */
orr_status h5r_read_main_header(hdf5_state *st, hid_t header, orr_source *src, orr_error *err)
{
    const char *path = st->first;
    int64_t counts[H5R_MAX_TYPES];
    orr_status s = read_counts(path, header, counts, &st->ntypes, err);
    int n = 0;
    if (!s)
        s = header_numbers(path, header, "MassTable", H5T_NATIVE_DOUBLE, st->mass_table, H5R_MAX_TYPES, 0, &n, err);
    if (!s && n != 0 && n != st->ntypes)
        s = orr_fail(err, ORR_ERR_FORMAT, "%s: Header/MassTable has %d entries but NumPart_ThisFile has %d", path, n,
                     st->ntypes);
    int64_t nfiles = 1;
    if (!s)
        s = header_numbers(path, header, "NumFilesPerSnapshot", H5T_NATIVE_INT64, &nfiles, 1, 0, &n, err);
    if (!s && nfiles > H5R_MAX_FILES)
        s = orr_fail(err, ORR_ERR_FORMAT, "%s: Header/NumFilesPerSnapshot = %" PRId64 " (at most %d are read)", path,
                     nfiles, H5R_MAX_FILES);
    double time = 0;
    if (!s)
        s = header_numbers(path, header, "Time", H5T_NATIVE_DOUBLE, &time, 1, 0, &n, err);
    if (s)
        return s;
    /* The time goes into every image's FITS header (and orders a sequence's
     * snapshots): a NaN or infinity there fails every render at its end. */
    if (!isfinite(time))
        return orr_fail(err, ORR_ERR_FORMAT, "%s: Header/Time = %g is not a finite number", path, time);
    src->info.time = time;
    /* Old IC writers leave 0 (or junk) for a single file. */
    st->nfiles = st->numbered && nfiles > 1 ? (int)nfiles : 1;
    if (nfiles > 1 && !st->numbered)
        orr_source_add_header(&src->info, "note",
                              "NumFilesPerSnapshot = %" PRId64 " but the name is not base.N.ext: reading this file only",
                              nfiles);
    return ORR_OK;
}

/* ---- Checking groups and datasets ----------------------------------- */

static void format_shape(char *buf, size_t size, int rank, const hsize_t *dims)
{
    size_t len = (size_t)snprintf(buf, size, "(");
    for (int i = 0; i < rank && len < size; i++)
        len += (size_t)snprintf(buf + len, size - len, "%s%llu", i ? ", " : "", (unsigned long long)dims[i]);
    if (len < size)
        snprintf(buf + len, size - len, "%s)", rank == 1 ? "," : "");
}

static const char *class_name(H5T_class_t cls)
{
    switch (cls) {
    case H5T_INTEGER: return "integer";
    case H5T_FLOAT: return "float";
    case H5T_STRING: return "string";
    case H5T_COMPOUND: return "compound";
    case H5T_ARRAY: return "array";
    default: return "non-numeric";
    }
}

/* Checks one dataset against the particle count the header gives. */
static orr_status check_dataset(const char *path, int type, hid_t group, const char *name, h5r_dataset kind,
                                int64_t n, orr_error *err)
{
    char why[256];
    hid_t ds = H5Dopen2(group, name, H5P_DEFAULT);
    if (ds < 0) {
        orr_h5_reason(why, sizeof why);
        return orr_fail(err, ORR_ERR_FORMAT, "%s: PartType%d/%s is not a readable dataset (%s)", path, type, name,
                        why);
    }
    hsize_t dims[ORR_H5_MAX_RANK];
    H5T_class_t cls = H5T_NO_CLASS;
    int rank = orr_h5_dataset_shape(ds, dims, &cls);
    orr_h5_storage store;
    orr_h5_storage_info(ds, &store);
    orr_h5_close(ds);
    int ncols = kind == DS_POS || kind == DS_VEL ? 3 : 0;
    char shape[128];
    if (rank < 0) {
        orr_h5_reason(why, sizeof why);
        return orr_fail(err, ORR_ERR_FORMAT, "%s: PartType%d/%s: cannot read its shape (%s)", path, type, name, why);
    }
    format_shape(shape, sizeof shape, rank, dims);
    if (rank != (ncols ? 2 : 1) || (ncols && dims[1] != (hsize_t)ncols))
        return orr_fail(err, ORR_ERR_FORMAT, "%s: PartType%d/%s has shape %s; expected (%" PRId64 "%s)", path, type,
                        name, shape, n, ncols ? ", 3" : ",");
    if (dims[0] != (hsize_t)n)
        return orr_fail(err, ORR_ERR_FORMAT, "%s: PartType%d/%s has %llu rows but Header/NumPart_ThisFile[%d] = %" PRId64,
                        path, type, name, (unsigned long long)dims[0], type, n);
    if (kind == DS_ID ? cls != H5T_INTEGER : cls != H5T_INTEGER && cls != H5T_FLOAT)
        return orr_fail(err, ORR_ERR_FORMAT, "%s: PartType%d/%s holds %s values; expected %s", path, type, name,
                        class_name(cls), kind == DS_ID ? "integers" : "numbers");
    if (store.chunk_bytes > H5R_MAX_HDF5_CHUNK_BYTES)
        return orr_fail(err, ORR_ERR_FORMAT, "%s: PartType%d/%s is stored in HDF5 chunks of %llu bytes (at most %llu)",
                        path, type, name, (unsigned long long)store.chunk_bytes,
                        (unsigned long long)H5R_MAX_HDF5_CHUNK_BYTES);
    double logical = (double)n * (ncols ? ncols : 1) * (double)store.element_bytes;
    if (!store.is_virtual && (double)store.stored_bytes * H5R_MAX_COMPRESSION < logical)
        return orr_fail(err, ORR_ERR_FORMAT,
                        "%s: PartType%d/%s claims %" PRId64 " rows but only %llu bytes are stored: rows never written?",
                        path, type, name, n, (unsigned long long)store.stored_bytes);
    return ORR_OK;
}

/* Checks the group of type t in a file holding n particles of it; records
 * which datasets it has in present[] and example[] (for unit entries). */
static orr_status check_group(hdf5_state *st, const char *path, hid_t fid, int t, int64_t n, char example[DS_COUNT][H5R_GROUP_NAME],
                              orr_error *err)
{
    char gname[H5R_GROUP_NAME];
    snprintf(gname, sizeof gname, "PartType%d", t);
    if (!orr_h5_has_link(fid, gname))
        return orr_fail(err, ORR_ERR_FORMAT, "%s: Header/NumPart_ThisFile[%d] = %" PRId64 " but there is no %s group",
                        path, t, n, gname);
    hid_t g = H5Gopen2(fid, gname, H5P_DEFAULT);
    if (g < 0) {
        char why[256];
        orr_h5_reason(why, sizeof why);
        return orr_fail(err, ORR_ERR_FORMAT, "%s: %s is not a readable group (%s)", path, gname, why);
    }
    orr_status s = ORR_OK;
    for (int i = 0; i < st->nnamed && !s; i++)
        s = h5r_named_check(&st->named[i], path, t, g, n, err);
    for (int k = 0; k < DS_COUNT && !s; k++) {
        const char *name = h5r_dataset_name_in(g, (h5r_dataset)k);
        if (!name && k == DS_POS)
            s = orr_fail(err, ORR_ERR_FORMAT, "%s: %s has no Coordinates dataset", path, gname);
        else if (!name && k == DS_MASS && st->mass_table[t] == 0)
            s = orr_fail(err, ORR_ERR_FORMAT, "%s: %s has no Masses dataset and Header/MassTable[%d] is 0", path,
                         gname, t);
        else if (!name && k == DS_MASS && orr_mass_problem(st->mass_table[t]))
            s = orr_fail(err, ORR_ERR_FORMAT, "%s: %s has no Masses dataset and Header/MassTable[%d] = %g %s", path,
                         gname, t, st->mass_table[t], orr_mass_problem(st->mass_table[t]));
        else if (name)
            s = check_dataset(path, t, g, name, (h5r_dataset)k, n, err);
        if (name && !s) {
            st->present[k] = 1;
            if (k == DS_H && strcmp(name, "SmoothingLengths") == 0)
                st->swift_h = 1;
            if (!example[k][0])
                snprintf(example[k], sizeof example[k], "%s", gname);
        }
    }
    orr_h5_close(g);
    return s;
}

/* Whether a file has any PartTypeN group at all. */
static int has_any_group(hid_t fid, int ntypes)
{
    char gname[H5R_GROUP_NAME];
    for (int t = 0; t < ntypes; t++) {
        snprintf(gname, sizeof gname, "PartType%d", t);
        if (orr_h5_has_link(fid, gname))
            return 1;
    }
    return 0;
}

/* The rows of the first dataset the reader knows in group g (0 when it has
 * none); *name gets that dataset's name. */
static uint64_t group_rows(hid_t g, const char **name)
{
    for (int k = 0; k < DS_COUNT; k++) {
        *name = h5r_dataset_name_in(g, (h5r_dataset)k);
        if (!*name)
            continue;
        hid_t ds = H5Dopen2(g, *name, H5P_DEFAULT);
        hsize_t dims[ORR_H5_MAX_RANK];
        H5T_class_t cls = H5T_NO_CLASS;
        int rank = ds >= 0 ? orr_h5_dataset_shape(ds, dims, &cls) : -1;
        orr_h5_close(ds);
        H5Eclear2(H5E_DEFAULT);
        if (rank >= 1 && dims[0] > 0)
            return (uint64_t)dims[0];
    }
    return 0;
}

/* A type the header counts 0 of is never read, so rows in its group would
 * be dropped without a word (a header with NumPart_ThisFile all 0 would give
 * an empty image): the header and the data disagree, and neither can be
 * trusted. Checked for every type, wanted or not. */
static orr_status check_uncounted_group(const char *path, hid_t fid, int t, orr_error *err)
{
    char gname[H5R_GROUP_NAME];
    snprintf(gname, sizeof gname, "PartType%d", t);
    if (!orr_h5_has_link(fid, gname))
        return ORR_OK;
    hid_t g = H5Gopen2(fid, gname, H5P_DEFAULT);
    if (g < 0) {
        H5Eclear2(H5E_DEFAULT);
        return ORR_OK; /* not read, and nothing in it can be seen */
    }
    const char *name = NULL;
    uint64_t rows = group_rows(g, &name);
    orr_h5_close(g);
    if (rows == 0)
        return ORR_OK;
    return orr_fail(err, ORR_ERR_FORMAT,
                    "%s: Header/NumPart_ThisFile[%d] = 0 but %s/%s has %llu rows: the header and the datasets "
                    "disagree",
                    path, t, gname, name, (unsigned long long)rows);
}

/* Checks file i (already open as fid): its counts and every wanted group. */
static orr_status check_file(hdf5_state *st, int i, hid_t fid, char example[DS_COUNT][H5R_GROUP_NAME], int *any_group,
                             orr_error *err)
{
    char path[ORR_PATH_MAX];
    h5r_file_name(st, i, path, sizeof path);
    hid_t header = -1;
    int64_t *counts = st->npart + (size_t)i * (size_t)st->ntypes;
    /* Read in full first: npart has room for st->ntypes entries per file
     * only, and this file may have more. */
    int64_t file_counts[H5R_MAX_TYPES];
    int ntypes = 0;
    orr_status s = h5r_open_header(path, fid, &header, err);
    if (!s)
        s = read_counts(path, header, file_counts, &ntypes, err);
    orr_h5_close(header);
    if (!s && ntypes != st->ntypes)
        s = orr_fail(err, ORR_ERR_FORMAT, "%s: Header/NumPart_ThisFile has %d entries but %s has %d", path, ntypes,
                     st->first, st->ntypes);
    if (!s)
        memcpy(counts, file_counts, (size_t)ntypes * sizeof *counts);
    int64_t sum = 0;
    for (int t = 0; t < st->ntypes && !s; t++)
        sum += counts[t] > INT64_MAX / 64 ? INT64_MAX / 64 : counts[t];
    int groups = s ? 0 : has_any_group(fid, st->ntypes);
    if (!s && !groups && sum > 0)
        s = orr_fail(err, ORR_ERR_FORMAT, "%s: no PartType0..PartType%d group, although Header/NumPart_ThisFile says %" PRId64
                     " particles", path, st->ntypes - 1, sum);
    for (int t = 0; t < st->ntypes && !s; t++)
        if (counts[t] > 0 && (st->type_mask >> t & 1u))
            s = check_group(st, path, fid, t, counts[t], example, err);
        else if (counts[t] == 0)
            s = check_uncounted_group(path, fid, t, err);
    *any_group |= groups;
    return s;
}

/* Opens and checks every file; fills st->npart and the info counts. */
orr_status h5r_check_files(hdf5_state *st, hid_t first_fid, orr_source *src, char example[DS_COUNT][H5R_GROUP_NAME],
                           orr_error *err)
{
    st->npart = orr_calloc((size_t)st->nfiles * (size_t)st->ntypes, sizeof *st->npart, "HDF5 particle counts", err);
    if (!st->npart)
        return ORR_ERR_NOMEM;
    int any_group = 0;
    orr_status s = ORR_OK;
    for (int i = 0; i < st->nfiles && !s; i++) {
        char path[ORR_PATH_MAX];
        h5r_file_name(st, i, path, sizeof path);
        /* The name given may be any file of the snapshot, not only file 0. */
        int reuse = strcmp(path, st->first) == 0;
        hid_t fid = reuse ? first_fid : -1;
        if (!reuse) {
            char context[ORR_PATH_MAX + 96];
            snprintf(context, sizeof context, " (file %d of %d of the snapshot, by Header/NumFilesPerSnapshot of %s)",
                     i + 1, st->nfiles, st->first);
            s = h5r_open_file(path, &fid, context, err);
        }
        if (!s)
            s = check_file(st, i, fid, example, &any_group, err);
        if (!reuse)
            orr_h5_close(fid);
    }
    if (!s && !any_group)
        s = orr_fail(err, ORR_ERR_FORMAT, "%s: no PartType0..PartType%d group: the snapshot holds no particles",
                     st->first, st->ntypes - 1);
    int64_t total = 0;
    for (int i = 0; i < st->nfiles && !s; i++)
        for (int t = 0; t < st->ntypes; t++)
            if (st->type_mask >> t & 1u) {
                int64_t n = st->npart[(size_t)i * (size_t)st->ntypes + (size_t)t];
                if (n > INT64_MAX - total)
                    return orr_fail(err, ORR_ERR_FORMAT, "%s: more than 2^63 particles claimed", st->first);
                total += n;
            }
    src->info.count = total;
    return s;
}
