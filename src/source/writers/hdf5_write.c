#define _GNU_SOURCE /* memfd_create */
#include "source/writers/hdf5_write.h"

#include <errno.h>
#include <string.h>
#include <sys/mman.h>
#include <unistd.h>

#include "core/atomic.h"

int orr_h5w_attr(hid_t loc, const char *name, hid_t ftype, hid_t mtype, const void *v, int n)
{
    hsize_t dims[1] = {(hsize_t)n};
    hid_t space = n ? H5Screate_simple(1, dims, NULL) : H5Screate(H5S_SCALAR);
    hid_t a = space >= 0 ? H5Acreate2(loc, name, ftype, space, H5P_DEFAULT, H5P_DEFAULT) : -1;
    int bad = a < 0 || H5Awrite(a, mtype, v) < 0;
    if (a >= 0 && H5Aclose(a) < 0)
        bad = 1;
    if (space >= 0)
        H5Sclose(space);
    return bad;
}

int orr_h5w_double(hid_t loc, const char *name, double v)
{
    return orr_h5w_attr(loc, name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, &v, 0);
}

int orr_h5w_string(hid_t loc, const char *name, const char *s)
{
    hid_t type = H5Tcopy(H5T_C_S1);
    if (type < 0 || H5Tset_size(type, strlen(s) ? strlen(s) : 1) < 0) {
        if (type >= 0)
            H5Tclose(type);
        return 1;
    }
    int bad = orr_h5w_attr(loc, name, type, type, s, 0);
    H5Tclose(type);
    return bad;
}

/* Object creation properties without modification times, so that the same
 * contents give the same bytes. */
static hid_t untimed(hid_t class_id)
{
    hid_t p = H5Pcreate(class_id);
    if (p >= 0)
        H5Pset_obj_track_times(p, 0);
    return p;
}

hid_t orr_h5w_group(hid_t loc, const char *name)
{
    hid_t gcpl = untimed(H5P_GROUP_CREATE);
    hid_t g = H5Gcreate2(loc, name, H5P_DEFAULT, gcpl, H5P_DEFAULT);
    if (gcpl >= 0)
        H5Pclose(gcpl);
    return g;
}

int orr_h5w_dataset(hid_t group, const char *name, hid_t ftype, hid_t mtype, const void *data, hsize_t rows,
                    int cols)
{
    hsize_t dims[2] = {rows, (hsize_t)cols};
    hid_t space = H5Screate_simple(cols > 1 ? 2 : 1, dims, NULL);
    hid_t dcpl = untimed(H5P_DATASET_CREATE);
    hid_t ds = space >= 0 && dcpl >= 0 ? H5Dcreate2(group, name, ftype, space, H5P_DEFAULT, dcpl, H5P_DEFAULT) : -1;
    int bad = ds < 0 || H5Dwrite(ds, mtype, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) < 0;
    /* The close writes what HDF5 still holds of the data (a full disk
     * fails here, not in H5Dwrite). */
    if (ds >= 0 && H5Dclose(ds) < 0)
        bad = 1;
    if (dcpl >= 0)
        H5Pclose(dcpl);
    if (space >= 0)
        H5Sclose(space);
    return bad;
}

int orr_h5w_close_group(hid_t group, int bad) { return H5Gclose(group) < 0 || bad; }

/* HDF5 cannot close a file whose flush fails (a full disk): it keeps it
 * half closed, and a second close, or the library's end at exit, crashes
 * ("infinite loop closing library", then a segfault). So the file is
 * flushed first, and when that or any write failed, the temporary file is
 * given up before the close: HDF5's descriptor is pointed at an empty file
 * in memory, where the close's own flush succeeds. */
static void give_up_file(hid_t file)
{
    void *handle = NULL; /* the default (POSIX) driver's: an int descriptor */
    if (H5Fget_vfd_handle(file, H5P_DEFAULT, &handle) < 0 || !handle)
        return;
    int scratch = memfd_create("orrery-hdf5-given-up", MFD_CLOEXEC);
    if (scratch < 0)
        return;
    dup2(scratch, *(int *)handle);
    close(scratch);
}

orr_status orr_h5w_write_file(const char *path, orr_h5w_body write_body, void *ctx, orr_error *err)
{
    orr_atomic_file af;
    orr_status st = orr_atomic_begin(&af, path, err);
    if (st)
        return st;
    /* A file HDF5 could not close (give_up_file's own file full too, under
     * `ulimit -f`) would crash the library's end at exit: when this is the
     * process's first HDF5 call, it is told not to end itself at exit (a
     * no-op once HDF5 is in use; the OS closes what is left). */
    H5dont_atexit();
    /* HDF5 prints its error stack by default; the library never prints. */
    H5E_auto2_t old_fn;
    void *old_data;
    H5Eget_auto2(H5E_DEFAULT, &old_fn, &old_data);
    H5Eset_auto2(H5E_DEFAULT, NULL, NULL);
    hid_t fcpl = untimed(H5P_FILE_CREATE); /* the root group's times */
    hid_t file = H5Fcreate(af.temp_path, H5F_ACC_TRUNC, fcpl, H5P_DEFAULT);
    if (fcpl >= 0)
        H5Pclose(fcpl);
    /* HDF5's messages do not give the system's reason (a full disk), so
     * errno is read right after the call that failed: the write, or the
     * close that flushes HDF5's cached metadata. */
    errno = 0;
    int bad = file < 0 || write_body(file, ctx) || H5Fflush(file, H5F_SCOPE_GLOBAL) < 0;
    int sys_errno = bad ? errno : 0;
    if (bad && file >= 0)
        give_up_file(file);
    errno = 0;
    if (file >= 0 && H5Fclose(file) < 0) {
        bad = 1;
        sys_errno = sys_errno ? sys_errno : errno;
    }
    H5Eset_auto2(H5E_DEFAULT, old_fn, old_data);
    if (bad) {
        orr_atomic_abort(&af);
        if (sys_errno)
            return orr_fail(err, ORR_ERR_IO, "%s: could not write the HDF5 snapshot: %s", path,
                            strerror(sys_errno));
        return orr_fail(err, ORR_ERR_IO, "%s: could not write the HDF5 snapshot (disk full or not writable?)",
                        path);
    }
    return orr_atomic_commit(&af, err);
}
