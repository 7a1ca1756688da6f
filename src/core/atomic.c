#include "core/atomic.h"
#include "core/digest.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdatomic.h>
#include <stdint.h>
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

/* ---- temporary names ---- */

/* 8 hex digits of the host name's digest, so that a folder shared between
 * machines never has one host remove another's files. */
static unsigned host_tag(void)
{
    char name[256] = "";
    gethostname(name, sizeof name - 1);
    return (unsigned)(orr_digest_text(ORR_DIGEST_START, name) & 0xffffffffu);
}

/* Creates "<dir>/.orrery-tmp-HOST-PID-N-<base>" exclusively, N counting up
 * from a process-wide counter, so that no two writers of this process, and
 * no other process, get the same name. A base too long for one name
 * component keeps only its extension, which the writers read the format
 * from. Returns the open descriptor, or -1 with errno. */
static int create_temp(char *out, size_t size, const char *final_path, const char *base)
{
    static atomic_uint counter;
    const char *ext = strrchr(base, '.');
    const char *tail = strlen(base) <= 160 ? base : ext ? ext : "";
    int dir_len = base == final_path ? 0 : (int)(base - final_path);
    for (int attempt = 0; attempt < 100; attempt++) {
        unsigned n = atomic_fetch_add(&counter, 1u);
        int len = snprintf(out, size, "%.*s" ORR_TEMP_PREFIX "%08x-%ld-%u-%s", dir_len, final_path, host_tag(),
                           (long)getpid(), n, tail);
        if (len < 0 || (size_t)len >= size) {
            errno = ENAMETOOLONG;
            return -1;
        }
        int fd = open(out, O_WRONLY | O_CREAT | O_EXCL, 0666); /* 0666 less the umask, like any file the user makes */
        if (fd >= 0 || errno != EEXIST)
            return fd;
    }
    errno = EEXIST;
    return -1;
}

/* ---- the temporaries a signal handler removes ---- */

/* A fixed table, so the handler needs no lock and no allocation: a slot is
 * free (0), being filled (1) or holds a live temporary (2). */
#define LIVE_SLOTS 64
static char live_path[LIVE_SLOTS][ORR_PATH_MAX];
static atomic_int live_state[LIVE_SLOTS];

static int live_add(const char *path)
{
    for (int i = 0; i < LIVE_SLOTS; i++) {
        int expected = 0;
        if (atomic_compare_exchange_strong(&live_state[i], &expected, 1)) {
            snprintf(live_path[i], sizeof live_path[i], "%s", path);
            atomic_store(&live_state[i], 2);
            return i;
        }
    }
    return -1; /* table full: the file is still removed by abort, or later as stale */
}

static void live_drop(int slot)
{
    if (slot >= 0)
        atomic_store(&live_state[slot], 0);
}

void orr_remove_live_temporaries(void)
{
    for (int i = 0; i < LIVE_SLOTS; i++)
        if (atomic_load(&live_state[i]) == 2)
            unlink(live_path[i]);
}

/* Whether process pid has ended: gone, or a zombie that its parent has not
 * reaped yet (kill(pid, 0) succeeds on one: a killed run's job processes
 * stay so until reaped, and a resume started meanwhile kept their
 * temporaries). The state is the field after the name in /proc/PID/stat. */
static int process_ended(long pid)
{
    if (kill((pid_t)pid, 0) != 0)
        return errno == ESRCH;
    char path[64], line[512];
    snprintf(path, sizeof path, "/proc/%ld/stat", pid);
    FILE *f = fopen(path, "r");
    if (!f)
        return 0; /* no /proc: alive, as kill says */
    size_t n = fread(line, 1, sizeof line - 1, f);
    fclose(f);
    line[n] = '\0';
    const char *end_of_name = strrchr(line, ')'); /* the name may hold spaces and ')' */
    return end_of_name && (end_of_name[1] == ' ') && (end_of_name[2] == 'Z' || end_of_name[2] == 'X');
}

/* Whether name is a temporary this process made. */
static int is_own_temporary(const char *name)
{
    char own[64];
    snprintf(own, sizeof own, ORR_TEMP_PREFIX "%08x-%ld-", host_tag(), (long)getpid());
    return strncmp(name, own, strlen(own)) == 0;
}

/* Whether name is a temporary of a process of this host that has ended. */
static int is_stale_temporary(const char *name, unsigned host)
{
    unsigned tag;
    long pid;
    int used = 0;
    if (strncmp(name, ORR_TEMP_PREFIX, strlen(ORR_TEMP_PREFIX)) != 0 ||
        sscanf(name + strlen(ORR_TEMP_PREFIX), "%8x-%ld-%n", &tag, &pid, &used) != 2 || used == 0)
        return 0;
    if (tag != host || pid <= 0 || pid == (long)getpid())
        return 0;
    return process_ended(pid);
}

int orr_remove_stale_temporaries(const char *dir)
{
    DIR *d = opendir(dir && dir[0] ? dir : ".");
    if (!d)
        return 0;
    unsigned host = host_tag();
    int removed = 0;
    struct dirent *e;
    while ((e = readdir(d)) != NULL) {
        char path[ORR_PATH_MAX];
        if (!is_stale_temporary(e->d_name, host) ||
            snprintf(path, sizeof path, "%s/%s", dir && dir[0] ? dir : ".", e->d_name) >= (int)sizeof path)
            continue;
        removed += unlink(path) == 0;
    }
    closedir(d);
    return removed;
}

/* ---- one file ---- */

orr_status orr_atomic_begin(orr_atomic_file *af, const char *final_path, orr_error *err)
{
    memset(af, 0, sizeof *af);
    af->live_slot = -1;
    char dir[ORR_PATH_MAX];
    const char *base;
    if (!final_path || !final_path[0])
        return orr_fail(err, ORR_ERR_USAGE, "output file name is empty");
    if (snprintf(af->final_path, sizeof af->final_path, "%s", final_path) >= (int)sizeof af->final_path ||
        !split_path(final_path, dir, sizeof dir, &base))
        return orr_fail(err, ORR_ERR_USAGE, "output path is too long: %.200s...", final_path);
    if (!base[0])
        return orr_fail(err, ORR_ERR_USAGE, "output path %s names a folder, not a file", final_path);
    struct stat st;
    if (stat(final_path, &st) == 0 && S_ISDIR(st.st_mode))
        return orr_fail(err, ORR_ERR_IO, "%s: a folder of that name is in the way of the output file", final_path);
    /* A writer handed one of this process's temporaries (a frame's output
     * batch) writes into it: a temporary of a temporary would only be a
     * longer name to clean up. The commit's rename is then to itself. */
    if (is_own_temporary(base)) {
        snprintf(af->temp_path, sizeof af->temp_path, "%s", final_path);
        return ORR_OK;
    }
    /* The temporary file lives in the target's own folder so that the final
     * rename never crosses file systems and is therefore atomic. */
    int fd = create_temp(af->temp_path, sizeof af->temp_path, final_path, base);
    if (fd < 0) {
        int e = errno;
        af->temp_path[0] = '\0';
        if (e == ENAMETOOLONG)
            return orr_fail(err, ORR_ERR_USAGE, "output path is too long: %.200s...", final_path);
        return orr_fail(err, ORR_ERR_IO, "output directory %s: cannot create a file there (for %s): %s", dir,
                        base, strerror(e));
    }
    close(fd);
    af->live_slot = live_add(af->temp_path);
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
    live_drop(af->live_slot);
    af->live_slot = -1;
    af->temp_path[0] = '\0';
    return ORR_OK;
}

void orr_atomic_abort(orr_atomic_file *af)
{
    if (af->temp_path[0])
        unlink(af->temp_path);
    live_drop(af->live_slot);
    af->live_slot = -1;
    af->temp_path[0] = '\0';
}

/* ---- a frame's outputs ---- */

void orr_output_batch_init(orr_output_batch *b) { memset(b, 0, sizeof *b); }

static void batch_free(orr_output_batch *b)
{
    for (int i = 0; i < b->n; i++)
        free(b->files[i]);
    free(b->files);
    orr_output_batch_init(b);
}

orr_status orr_output_batch_add(orr_output_batch *b, const char *final_path, const char **write_path,
                                orr_error *err)
{
    *write_path = NULL;
    for (int i = 0; i < b->n; i++)
        if (strcmp(b->files[i]->final_path, final_path) == 0)
            return orr_fail(err, ORR_ERR_USAGE, "%s: two outputs of one frame have this name", final_path);
    if (b->n == b->cap) {
        int cap = b->cap ? 2 * b->cap : 8;
        orr_atomic_file **files = realloc(b->files, (size_t)cap * sizeof *files);
        if (!files)
            return orr_fail(err, ORR_ERR_NOMEM, "out of memory for the list of a frame's outputs");
        b->files = files;
        b->cap = cap;
    }
    orr_atomic_file *af = orr_malloc(sizeof *af, "an output's names", err);
    if (!af)
        return ORR_ERR_NOMEM;
    orr_status st = orr_atomic_begin(af, final_path, err);
    if (st) {
        free(af);
        return st;
    }
    b->files[b->n++] = af;
    *write_path = af->temp_path;
    return ORR_OK;
}

orr_status orr_output_batch_commit(orr_output_batch *b, orr_error *err)
{
    orr_status st = ORR_OK;
    int done = 0;
    for (; done < b->n && !st; done++)
        st = orr_atomic_commit(b->files[done], err);
    if (st) {
        for (int i = done; i < b->n; i++)
            orr_atomic_abort(b->files[i]);
        if (done > 1)
            orr_fail_prefix(err, "%d of the frame's %d outputs were already in place, the rest are removed: ",
                            done - 1, b->n);
    }
    batch_free(b);
    return st;
}

void orr_output_batch_name_finals(const orr_output_batch *b, orr_error *err)
{
    if (!err)
        return;
    for (int i = 0; i < b->n; i++) {
        const char *temp = b->files[i]->temp_path, *at;
        if (!temp[0] || !(at = strstr(err->msg, temp)))
            continue;
        char msg[ORR_ERROR_MSG_MAX];
        if (snprintf(msg, sizeof msg, "%.*s%s%s", (int)(at - err->msg), err->msg, b->files[i]->final_path,
                     at + strlen(temp)) >= 0) /* a message cut short at its end is still the better one */
            memcpy(err->msg, msg, sizeof msg);
    }
}

void orr_output_batch_abort(orr_output_batch *b)
{
    for (int i = 0; i < b->n; i++)
        orr_atomic_abort(b->files[i]);
    batch_free(b);
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
