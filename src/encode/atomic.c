#include "encode/atomic.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* Splits path into its folder ("." when there is none) and its last
 * component. Returns 0 when either does not fit. */
static int split_path(const char *path, char *dir, size_t dir_size, const char **base)
{
    const char *slash = strrchr(path, '/');
    if (!slash) {
        *base = path;
        return snprintf(dir, dir_size, ".") < (int)dir_size;
    }
    *base = slash + 1;
    size_t len = (size_t)(slash - path);
    if (len == 0)
        len = 1; /* "/name": the folder is the root */
    if (len >= dir_size)
        return 0;
    memcpy(dir, path, len);
    dir[len] = '\0';
    return 1;
}

/* mkstemp creates files with mode 0600; outputs are images meant to be
 * shared like any other file the user creates, so give them the usual
 * 0666 less the umask. umask can only be read by setting it, so it is set
 * back at once (output files are written from a single thread). */
static void set_default_mode(int fd)
{
    mode_t mask = umask(022);
    umask(mask);
    (void)fchmod(fd, 0666 & ~mask);
}

orr_status orr_atomic_begin(orr_atomic_file *af, const char *final_path, orr_error *err)
{
    memset(af, 0, sizeof *af);
    char dir[ORR_PATH_MAX];
    const char *base;
    if (!final_path || !final_path[0])
        return orr_fail(err, ORR_ERR_USAGE, "output file name is empty");
    if (snprintf(af->final_path, sizeof af->final_path, "%s", final_path) >= (int)sizeof af->final_path ||
        !split_path(final_path, dir, sizeof dir, &base))
        return orr_fail(err, ORR_ERR_USAGE, "output path is too long: %.200s...", final_path);
    if (!base[0])
        return orr_fail(err, ORR_ERR_USAGE, "output path %s names a folder, not a file", final_path);
    /* The temporary file lives in the target's own folder so that the final
     * rename never crosses file systems and is therefore atomic. */
    int n = base == final_path ? snprintf(af->temp_path, sizeof af->temp_path, ".%s.tmp-XXXXXX", base)
                               : snprintf(af->temp_path, sizeof af->temp_path, "%.*s/.%s.tmp-XXXXXX",
                                          (int)(base - 1 - final_path), final_path, base);
    if (n < 0 || n >= (int)sizeof af->temp_path) {
        af->temp_path[0] = '\0';
        return orr_fail(err, ORR_ERR_USAGE, "output path is too long: %.200s...", final_path);
    }
    int fd = mkstemp(af->temp_path);
    if (fd < 0) {
        int e = errno;
        af->temp_path[0] = '\0';
        return orr_fail(err, ORR_ERR_IO, "output directory %s: cannot create a file there (for %s): %s", dir,
                        base, strerror(e));
    }
    set_default_mode(fd);
    close(fd);
    return ORR_OK;
}

orr_status orr_atomic_commit(orr_atomic_file *af, orr_error *err)
{
    if (!af->temp_path[0])
        return orr_fail(err, ORR_ERR_INTERNAL, "%s: no temporary file to commit", af->final_path);
    if (rename(af->temp_path, af->final_path) != 0) {
        int e = errno;
        orr_fail(err, ORR_ERR_IO, "cannot rename %s to %s: %s", af->temp_path, af->final_path, strerror(e));
        orr_atomic_abort(af);
        return ORR_ERR_IO;
    }
    /* The temporary name no longer exists; a later abort must not remove a
     * file some other process may have created under it since. */
    af->temp_path[0] = '\0';
    return ORR_OK;
}

void orr_atomic_abort(orr_atomic_file *af)
{
    if (af->temp_path[0])
        unlink(af->temp_path);
    af->temp_path[0] = '\0';
}

/* mkdir -p: creates dir and any missing folders above it. Returns 0 or an
 * errno value. Another process creating one meanwhile is fine. */
static int make_dirs(const char *dir)
{
    char path[ORR_PATH_MAX];
    if (snprintf(path, sizeof path, "%s", dir) >= (int)sizeof path)
        return ENAMETOOLONG;
    for (char *p = path + 1; *p; p++) {
        if (*p != '/')
            continue;
        *p = '\0';
        if (mkdir(path, 0777) != 0 && errno != EEXIST)
            return errno;
        *p = '/';
    }
    return mkdir(path, 0777) != 0 && errno != EEXIST ? errno : 0;
}

orr_status orr_check_output_dir(const char *dir, orr_error *err)
{
    if (!dir || !dir[0])
        dir = ".";
    struct stat st;
    if (stat(dir, &st) != 0) {
        int e = errno;
        if (e != ENOENT)
            return orr_fail(err, ORR_ERR_IO, "output directory %s: cannot access it: %s", dir, strerror(e));
        if ((e = make_dirs(dir)) != 0)
            return orr_fail(err, ORR_ERR_IO, "output directory %s: cannot create it: %s", dir, strerror(e));
    } else if (!S_ISDIR(st.st_mode)) {
        return orr_fail(err, ORR_ERR_IO, "output directory %s: exists but is not a directory", dir);
    }
    /* Permission bits do not tell the whole story (read-only mounts, ACLs,
     * root), so prove writability by creating and removing a file. */
    char probe[ORR_PATH_MAX];
    if (snprintf(probe, sizeof probe, "%s/.orrery-write-test-XXXXXX", dir) >= (int)sizeof probe)
        return orr_fail(err, ORR_ERR_USAGE, "output directory name is too long: %.200s...", dir);
    int fd = mkstemp(probe);
    if (fd < 0) {
        int e = errno;
        return orr_fail(err, ORR_ERR_IO, "output directory %s: cannot create a file there: %s", dir, strerror(e));
    }
    close(fd);
    unlink(probe);
    return ORR_OK;
}
