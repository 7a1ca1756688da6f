/* Named HDF5 fields (hdf5_named.h). */
#include "source/readers/hdf5_named.h"

#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "source/readers/hdf5_util.h"
#include "source/source.h"

int h5r_named_parse(const char *field, h5r_named *out)
{
    if (strlen(field) >= sizeof out->field || strpbrk(field, "/."))
        return 0;
    if (!orr_field_split_column(field, out->dataset, sizeof out->dataset, &out->column))
        return 0;
    snprintf(out->field, sizeof out->field, "%s", field);
    out->present = 0;
    out->slot = -1;
    out->ds = -1;
    return 1;
}

orr_status h5r_named_check(h5r_named *f, const char *path, int t, hid_t g, int64_t n, orr_error *err)
{
    if (!orr_h5_has_link(g, f->dataset))
        return ORR_OK;
    hid_t ds = H5Dopen2(g, f->dataset, H5P_DEFAULT);
    hsize_t dims[ORR_H5_MAX_RANK];
    H5T_class_t cls = H5T_NO_CLASS;
    int rank = ds >= 0 ? orr_h5_dataset_shape(ds, dims, &cls) : -1;
    orr_h5_close(ds);
    const char *want = f->column < 0 ? "a 1-D dataset (for one column of a 2-D one: NAME[k])" : "a 2-D dataset";
    if (rank < 0)
        return orr_fail(err, ORR_ERR_FORMAT, "%s: PartType%d/%s is not a readable dataset", path, t, f->dataset);
    if (rank != (f->column < 0 ? 1 : 2))
        return orr_fail(err, ORR_ERR_FORMAT, "%s: PartType%d/%s has %d dimensions: field %s needs %s", path, t,
                        f->dataset, rank, f->field, want);
    if (dims[0] != (hsize_t)n)
        return orr_fail(err, ORR_ERR_FORMAT, "%s: PartType%d/%s has %llu rows but Header/NumPart_ThisFile[%d] = %" PRId64,
                        path, t, f->dataset, (unsigned long long)dims[0], t, n);
    if (f->column >= 0 && (hsize_t)f->column >= dims[1])
        return orr_fail(err, ORR_ERR_FORMAT, "%s: PartType%d/%s has %llu columns: field %s asks for column %d", path,
                        t, f->dataset, (unsigned long long)dims[1], f->field, f->column);
    if (cls != H5T_INTEGER && cls != H5T_FLOAT)
        return orr_fail(err, ORR_ERR_FORMAT, "%s: PartType%d/%s does not hold numbers: it cannot be field %s", path,
                        t, f->dataset, f->field);
    f->present = 1;
    return ORR_OK;
}

orr_status h5r_named_open(h5r_named *f, const char *path, int t, hid_t g, orr_error *err)
{
    f->ds = -1;
    if (!orr_h5_has_link(g, f->dataset))
        return ORR_OK;
    f->ds = H5Dopen2(g, f->dataset, H5P_DEFAULT);
    if (f->ds < 0)
        return orr_fail(err, ORR_ERR_FORMAT, "%s: PartType%d/%s cannot be opened", path, t, f->dataset);
    return ORR_OK;
}

orr_status h5r_named_read(const h5r_named *f, const char *path, int t, uint64_t row, size_t n, float *out,
                          orr_error *err)
{
    if (f->ds < 0) { /* a type without the dataset: 0, as for every other extra field */
        memset(out, 0, n * sizeof *out);
        return ORR_OK;
    }
    int bad = f->column < 0 ? orr_h5_read_rows(f->ds, row, n, 0, H5T_NATIVE_FLOAT, out)
                            : orr_h5_read_column(f->ds, row, n, f->column, H5T_NATIVE_FLOAT, out);
    if (!bad)
        return ORR_OK;
    char why[256];
    orr_h5_reason(why, sizeof why);
    return orr_fail(err, ORR_ERR_FORMAT, "%s: PartType%d/%s: reading rows %" PRIu64 " to %" PRIu64 " failed (%s)", path,
                    t, f->dataset, row, row + n - 1, why[0] ? why : "no reason given");
}

/* Appends the names of group g's links to buf ("Coordinates, Masses, ..."),
 * as many as fit. */
static void list_links(hid_t g, char *buf, size_t size)
{
    H5G_info_t info;
    size_t used = strlen(buf);
    if (H5Gget_info(g, &info) < 0)
        return;
    for (hsize_t i = 0; i < info.nlinks && used + 1 < size; i++) {
        char name[ORR_FIELD_NAME_MAX * 2];
        if (H5Lget_name_by_idx(g, ".", H5_INDEX_NAME, H5_ITER_INC, i, name, sizeof name, H5P_DEFAULT) < 0)
            continue;
        int n = snprintf(buf + used, size - used, "%s%s", i ? ", " : "", name);
        if (n < 0 || (size_t)n >= size - used) {
            snprintf(buf + (size - 5 > used ? size - 5 : used), 5, "...");
            return;
        }
        used += (size_t)n;
    }
}

orr_status h5r_named_missing(const h5r_named *f, const char *path, hid_t fid, unsigned type_mask, int ntypes,
                             orr_error *err)
{
    char datasets[512] = "";
    char gname[32] = "";
    for (int t = 0; t < ntypes && !datasets[0]; t++) {
        snprintf(gname, sizeof gname, "PartType%d", t);
        if (!(type_mask >> t & 1u) || !orr_h5_has_link(fid, gname))
            continue;
        hid_t g = H5Gopen2(fid, gname, H5P_DEFAULT);
        if (g >= 0)
            list_links(g, datasets, sizeof datasets);
        orr_h5_close(g);
    }
    H5Eclear2(H5E_DEFAULT);
    if (!datasets[0])
        return orr_fail(err, ORR_ERR_USAGE, "%s: field %s: no group read has a dataset %s", path, f->field,
                        f->dataset);
    return orr_fail(err, ORR_ERR_USAGE, "%s: field %s: no group read has a dataset %s (%s has: %s)", path, f->field,
                    f->dataset, gname, datasets);
}
