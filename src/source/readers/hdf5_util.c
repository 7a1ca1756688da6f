#include "source/readers/hdf5_util.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void orr_h5_quiet(void)
{
    H5Eset_auto2(H5E_DEFAULT, NULL, NULL);
}

typedef struct reason_buf {
    char *buf;
    size_t size;
    int found;
} reason_buf;

/* Walking upward, the first entry is the innermost, most specific failure
 * ("truncated file: eof = ..."), which is the useful one in a message. */
static herr_t take_first(unsigned n, const H5E_error2_t *e, void *data)
{
    (void)n;
    reason_buf *r = data;
    if (!r->found && e->desc && e->desc[0]) {
        snprintf(r->buf, r->size, "%s", e->desc);
        r->found = 1;
    }
    return 0;
}

const char *orr_h5_reason(char *buf, size_t size)
{
    reason_buf r = {buf, size, 0};
    if (size)
        buf[0] = '\0';
    H5Ewalk2(H5E_DEFAULT, H5E_WALK_UPWARD, take_first, &r);
    H5Eclear2(H5E_DEFAULT);
    return buf;
}

hid_t orr_h5_close(hid_t id)
{
    if (id >= 0 && H5Iis_valid(id) > 0)
        H5Idec_ref(id);
    return -1;
}

int orr_h5_has_link(hid_t loc, const char *name)
{
    /* H5Lexists fails (rather than answering no) on names with '/' whose
     * parents are missing; snapshot names have none. */
    htri_t r = H5Lexists(loc, name, H5P_DEFAULT);
    if (r < 0)
        H5Eclear2(H5E_DEFAULT);
    return r > 0;
}

orr_h5_attr_result orr_h5_attr_numbers(hid_t loc, const char *name, hid_t memtype, void *out, int max,
                                       int *count)
{
    *count = 0;
    htri_t exists = H5Aexists(loc, name);
    if (exists == 0)
        return ORR_H5_ABSENT;
    if (exists < 0)
        return ORR_H5_UNREADABLE;
    orr_h5_attr_result res = ORR_H5_UNREADABLE;
    hid_t attr = H5Aopen(loc, name, H5P_DEFAULT);
    hid_t type = attr >= 0 ? H5Aget_type(attr) : -1;
    hid_t space = attr >= 0 ? H5Aget_space(attr) : -1;
    if (type >= 0 && space >= 0) {
        H5T_class_t cls = H5Tget_class(type);
        hssize_t n = H5Sget_simple_extent_npoints(space);
        if (cls != H5T_INTEGER && cls != H5T_FLOAT) {
            res = ORR_H5_WRONG_TYPE;
        } else if (n < 1 || n > max) {
            *count = n < 0 ? 0 : (n > 1000000000 ? 1000000000 : (int)n);
            res = n < 1 ? ORR_H5_WRONG_TYPE : ORR_H5_TOO_MANY;
        } else if (H5Aread(attr, memtype, out) >= 0) {
            *count = (int)n;
            res = ORR_H5_FOUND;
        }
    }
    orr_h5_close(space);
    orr_h5_close(type);
    orr_h5_close(attr);
    return res;
}

/* Reads a fixed-length string attribute of type ftype into buf. */
static int read_fixed_string(hid_t attr, hid_t ftype, char *buf, size_t size)
{
    size_t len = H5Tget_size(ftype);
    if (len == 0 || len > (1u << 20))
        return -1;
    char *tmp = calloc(1, len + 1);
    hid_t mem = H5Tcopy(H5T_C_S1);
    int ok = tmp && mem >= 0 && H5Tset_size(mem, len) >= 0 && H5Aread(attr, mem, tmp) >= 0;
    if (ok)
        snprintf(buf, size, "%s", tmp);
    orr_h5_close(mem);
    free(tmp);
    return ok ? 0 : -1;
}

static int read_variable_string(hid_t attr, char *buf, size_t size)
{
    char *s = NULL;
    hid_t mem = H5Tcopy(H5T_C_S1);
    int ok = mem >= 0 && H5Tset_size(mem, H5T_VARIABLE) >= 0 && H5Aread(attr, mem, &s) >= 0;
    if (ok)
        snprintf(buf, size, "%s", s ? s : "");
    if (s)
        H5free_memory(s);
    orr_h5_close(mem);
    return ok ? 0 : -1;
}

orr_h5_attr_result orr_h5_attr_string(hid_t loc, const char *name, char *buf, size_t size)
{
    if (size)
        buf[0] = '\0';
    htri_t exists = H5Aexists(loc, name);
    if (exists == 0)
        return ORR_H5_ABSENT;
    if (exists < 0)
        return ORR_H5_UNREADABLE;
    orr_h5_attr_result res = ORR_H5_UNREADABLE;
    hid_t attr = H5Aopen(loc, name, H5P_DEFAULT);
    hid_t type = attr >= 0 ? H5Aget_type(attr) : -1;
    hid_t space = attr >= 0 ? H5Aget_space(attr) : -1;
    if (type >= 0 && space >= 0) {
        if (H5Tget_class(type) != H5T_STRING || H5Sget_simple_extent_npoints(space) != 1)
            res = ORR_H5_WRONG_TYPE;
        else if (H5Tis_variable_str(type) > 0)
            res = read_variable_string(attr, buf, size) == 0 ? ORR_H5_FOUND : ORR_H5_UNREADABLE;
        else
            res = read_fixed_string(attr, type, buf, size) == 0 ? ORR_H5_FOUND : ORR_H5_UNREADABLE;
    }
    orr_h5_close(space);
    orr_h5_close(type);
    orr_h5_close(attr);
    return res;
}

int orr_h5_dataset_shape(hid_t ds, hsize_t *dims, H5T_class_t *cls)
{
    hid_t space = H5Dget_space(ds);
    hid_t type = H5Dget_type(ds);
    int rank = -1;
    if (space >= 0 && type >= 0 && H5Sget_simple_extent_type(space) == H5S_SIMPLE) {
        rank = H5Sget_simple_extent_ndims(space);
        if (rank > ORR_H5_MAX_RANK || H5Sget_simple_extent_dims(space, dims, NULL) < 0)
            rank = -1;
        *cls = H5Tget_class(type);
    }
    orr_h5_close(type);
    orr_h5_close(space);
    return rank;
}

void orr_h5_storage_info(hid_t ds, orr_h5_storage *out)
{
    memset(out, 0, sizeof *out);
    hid_t plist = H5Dget_create_plist(ds);
    hid_t type = H5Dget_type(ds);
    if (type >= 0)
        out->element_bytes = H5Tget_size(type);
    out->stored_bytes = H5Dget_storage_size(ds);
    H5D_layout_t layout = plist >= 0 ? H5Pget_layout(plist) : H5D_LAYOUT_ERROR;
    out->is_virtual = layout == H5D_VIRTUAL;
    if (layout == H5D_CHUNKED) {
        hsize_t dims[ORR_H5_MAX_RANK];
        int rank = H5Pget_chunk(plist, ORR_H5_MAX_RANK, dims);
        uint64_t bytes = out->element_bytes;
        for (int i = 0; i < rank; i++)
            bytes = dims[i] && bytes > UINT64_MAX / dims[i] ? UINT64_MAX : bytes * dims[i];
        out->chunk_bytes = bytes;
    }
    orr_h5_close(type);
    orr_h5_close(plist);
    H5Eclear2(H5E_DEFAULT);
}



/* Reads the hyperslab start/count of ds into buf, shaped as mcount[0..mrank). */
static int read_slab(hid_t ds, const hsize_t *start, const hsize_t *count, int mrank, const hsize_t *mcount,
                     hid_t memtype, void *buf)
{
    hid_t fspace = H5Dget_space(ds);
    hid_t mspace = H5Screate_simple(mrank, mcount, NULL);
    int ok = fspace >= 0 && mspace >= 0 &&
             H5Sselect_hyperslab(fspace, H5S_SELECT_SET, start, NULL, count, NULL) >= 0 &&
             H5Dread(ds, memtype, mspace, fspace, H5P_DEFAULT, buf) >= 0;
    orr_h5_close(mspace);
    orr_h5_close(fspace);
    return ok ? 0 : -1;
}

int orr_h5_read_rows(hid_t ds, uint64_t first, size_t n, int ncols, hid_t memtype, void *buf)
{
    hsize_t start[2] = {first, 0};
    hsize_t count[2] = {n, (hsize_t)ncols};
    return read_slab(ds, start, count, ncols > 0 ? 2 : 1, count, memtype, buf);
}

int orr_h5_read_column(hid_t ds, uint64_t first, size_t n, int col, hid_t memtype, void *buf)
{
    hsize_t start[2] = {first, (hsize_t)col};
    hsize_t count[2] = {n, 1};
    return read_slab(ds, start, count, 1, count, memtype, buf);
}
