#include <dirent.h>
#include <errno.h>
#include <signal.h>
#include <stdlib.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "check.h"
#include "core/atomic.h"

static char tmpdir[256];

static void make_tmpdir(void)
{
    snprintf(tmpdir, sizeof tmpdir, "/tmp/orr_test_atomic_XXXXXX");
    if (!mkdtemp(tmpdir)) {
        perror("mkdtemp");
        exit(1);
    }
}

/* Removes the test folder's contents (one level of sub-folders is enough). */
static void remove_tree(const char *dir)
{
    DIR *d = opendir(dir);
    if (!d)
        return;
    struct dirent *e;
    while ((e = readdir(d))) {
        if (!strcmp(e->d_name, ".") || !strcmp(e->d_name, ".."))
            continue;
        char p[1024];
        snprintf(p, sizeof p, "%s/%s", dir, e->d_name);
        if (unlink(p) != 0)
            remove_tree(p);
    }
    closedir(d);
    rmdir(dir);
}

static int count_entries(const char *dir)
{
    DIR *d = opendir(dir);
    if (!d)
        return -1;
    int n = 0;
    struct dirent *e;
    while ((e = readdir(d)))
        if (strcmp(e->d_name, ".") && strcmp(e->d_name, ".."))
            n++;
    closedir(d);
    return n;
}

static int exists(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0;
}

static void write_text(const char *path, const char *text)
{
    FILE *f = fopen(path, "w");
    if (!f) {
        perror(path);
        exit(1);
    }
    fputs(text, f);
    fclose(f);
}

static int file_equals(const char *path, const char *text)
{
    char buf[256] = "";
    FILE *f = fopen(path, "r");
    if (!f)
        return 0;
    size_t n = fread(buf, 1, sizeof buf - 1, f);
    buf[n] = '\0';
    fclose(f);
    return strcmp(buf, text) == 0;
}

static void test_commit_renames_and_leaves_no_temp(void)
{
    make_tmpdir();
    char final[512], prefix[512];
    snprintf(final, sizeof final, "%s/out.png", tmpdir);
    snprintf(prefix, sizeof prefix, "%s/" ORR_TEMP_PREFIX, tmpdir);
    orr_atomic_file af;
    orr_error err;
    CHECK(orr_atomic_begin(&af, final, &err) == ORR_OK);
    CHECK(strncmp(af.temp_path, prefix, strlen(prefix)) == 0);
    CHECK(strcmp(af.temp_path + strlen(af.temp_path) - 8, "-out.png") == 0); /* keeps the extension */
    CHECK(exists(af.temp_path));
    CHECK(!exists(final));
    write_text(af.temp_path, "new");
    CHECK(orr_atomic_commit(&af, &err) == ORR_OK);
    CHECK(file_equals(final, "new"));
    CHECK(count_entries(tmpdir) == 1);
    /* The file gets the usual permissions, not mkstemp's 0600. */
    mode_t mask = umask(022);
    umask(mask);
    struct stat st;
    CHECK(stat(final, &st) == 0 && (st.st_mode & 0777) == (0666 & ~mask));
    /* An abort after a commit must not touch the final file. */
    orr_atomic_abort(&af);
    CHECK(file_equals(final, "new"));
    remove_tree(tmpdir);
}

static void test_abort_keeps_old_file(void)
{
    make_tmpdir();
    char final[512];
    snprintf(final, sizeof final, "%s/image.fits", tmpdir);
    write_text(final, "old");
    orr_atomic_file af;
    orr_error err;
    CHECK(orr_atomic_begin(&af, final, &err) == ORR_OK);
    write_text(af.temp_path, "half-written");
    orr_atomic_abort(&af);
    orr_atomic_abort(&af); /* twice is harmless */
    CHECK(file_equals(final, "old"));
    CHECK(count_entries(tmpdir) == 1);
    remove_tree(tmpdir);
}

static void test_abort_creates_nothing(void)
{
    make_tmpdir();
    char final[512];
    snprintf(final, sizeof final, "%s/new.png", tmpdir);
    orr_atomic_file af;
    orr_error err;
    CHECK(orr_atomic_begin(&af, final, &err) == ORR_OK);
    orr_atomic_abort(&af);
    CHECK(!exists(final));
    CHECK(count_entries(tmpdir) == 0);
    remove_tree(tmpdir);
}

static void test_relative_name_without_folder(void)
{
    make_tmpdir();
    char cwd[1024];
    CHECK(getcwd(cwd, sizeof cwd) != NULL);
    CHECK(chdir(tmpdir) == 0);
    orr_atomic_file af;
    orr_error err;
    CHECK(orr_atomic_begin(&af, "plain.png", &err) == ORR_OK);
    CHECK(strncmp(af.temp_path, ORR_TEMP_PREFIX, strlen(ORR_TEMP_PREFIX)) == 0);
    CHECK(orr_atomic_commit(&af, &err) == ORR_OK);
    CHECK(exists("plain.png"));
    CHECK(count_entries(".") == 1);
    CHECK(chdir(cwd) == 0);
    remove_tree(tmpdir);
}

static void test_begin_fails_in_unwritable_folder(void)
{
    make_tmpdir();
    char file[512], final[600];
    snprintf(file, sizeof file, "%s/regular", tmpdir);
    write_text(file, "x");
    snprintf(final, sizeof final, "%s/sub/out.png", file); /* a folder under a regular file */
    orr_atomic_file af;
    orr_error err;
    orr_error_clear(&err);
    CHECK(orr_atomic_begin(&af, final, &err) == ORR_ERR_IO);
    CHECK_CONTAINS(err.msg, "output directory");
    CHECK_CONTAINS(err.msg, file);
    CHECK_CONTAINS(err.msg, strerror(ENOTDIR));
    orr_atomic_abort(&af); /* harmless after a failed begin */
    CHECK(count_entries(tmpdir) == 1);
    CHECK(file_equals(file, "x"));
    remove_tree(tmpdir);
}

static void test_failed_commit_removes_temp(void)
{
    make_tmpdir();
    char final[512], inside[600];
    snprintf(final, sizeof final, "%s/taken", tmpdir);
    CHECK(mkdir(final, 0777) == 0);
    snprintf(inside, sizeof inside, "%s/keep", final);
    write_text(inside, "k"); /* a non-empty folder cannot be replaced by a file */
    orr_atomic_file af;
    orr_error err;
    /* A folder already in the way is refused before anything is written. */
    CHECK(orr_atomic_begin(&af, final, &err) == ORR_ERR_IO);
    CHECK_CONTAINS(err.msg, "a folder of that name");
    CHECK(count_entries(tmpdir) == 1);
    /* One that appears while the file is written fails the rename. */
    CHECK(unlink(inside) == 0 && rmdir(final) == 0);
    CHECK(orr_atomic_begin(&af, final, &err) == ORR_OK);
    CHECK(mkdir(final, 0777) == 0);
    write_text(inside, "k"); /* a non-empty folder cannot be replaced by a file */
    CHECK(orr_atomic_commit(&af, &err) == ORR_ERR_IO);
    CHECK_CONTAINS(err.msg, final);
    orr_atomic_abort(&af);
    CHECK(count_entries(tmpdir) == 1);
    CHECK(file_equals(inside, "k"));
    remove_tree(tmpdir);
}

/* A frame's outputs: renamed together, or none of them. */
static void test_batch_all_or_nothing(void)
{
    make_tmpdir();
    char a[512], b[512], c[512];
    snprintf(a, sizeof a, "%s/s.fits", tmpdir);
    snprintf(b, sizeof b, "%s/s.png", tmpdir);
    snprintf(c, sizeof c, "%s/s.exr", tmpdir);
    write_text(b, "old picture");
    orr_output_batch batch;
    orr_output_batch_init(&batch);
    const char *wa, *wb, *wc;
    orr_error err;
    CHECK(orr_output_batch_add(&batch, a, &wa, &err) == ORR_OK);
    CHECK(orr_output_batch_add(&batch, b, &wb, &err) == ORR_OK);
    CHECK(orr_output_batch_add(&batch, a, &wc, &err) == ORR_ERR_USAGE); /* the same name twice */
    write_text(wa, "new planes");
    write_text(wb, "new picture");
    CHECK(!exists(a) && file_equals(b, "old picture")); /* nothing in place before the commit */
    CHECK(orr_output_batch_commit(&batch, &err) == ORR_OK);
    CHECK(file_equals(a, "new planes") && file_equals(b, "new picture"));
    CHECK(count_entries(tmpdir) == 2);

    /* A failure before the commit: the batch is dropped whole. */
    CHECK(orr_output_batch_add(&batch, a, &wa, &err) == ORR_OK);
    CHECK(orr_output_batch_add(&batch, c, &wc, &err) == ORR_OK);
    write_text(wa, "newer planes");
    orr_output_batch_abort(&batch);
    CHECK(file_equals(a, "new planes") && !exists(c));
    CHECK(count_entries(tmpdir) == 2);
    remove_tree(tmpdir);
}

/* A writer (PNG, FITS, ...) is atomic on its own, and a frame's batch
 * hands it a temporary: it writes into that one, making no temporary of
 * the temporary (".orrery-tmp-...-.orrery-tmp-...png", which a kill left). */
static void test_no_temporary_of_a_temporary(void)
{
    make_tmpdir();
    char final[512];
    snprintf(final, sizeof final, "%s/s.png", tmpdir);
    orr_output_batch batch;
    orr_output_batch_init(&batch);
    const char *w;
    orr_error err;
    CHECK(orr_output_batch_add(&batch, final, &w, &err) == ORR_OK);
    orr_atomic_file inner;
    CHECK(orr_atomic_begin(&inner, w, &err) == ORR_OK);
    CHECK(strcmp(inner.temp_path, w) == 0);
    CHECK(count_entries(tmpdir) == 1); /* the batch's temporary alone */
    write_text(inner.temp_path, "picture");
    CHECK(orr_atomic_commit(&inner, &err) == ORR_OK);
    CHECK(orr_output_batch_commit(&batch, &err) == ORR_OK);
    CHECK(file_equals(final, "picture") && count_entries(tmpdir) == 1);
    /* A writer that fails removes it; the batch's abort then finds nothing. */
    CHECK(orr_output_batch_add(&batch, final, &w, &err) == ORR_OK);
    CHECK(orr_atomic_begin(&inner, w, &err) == ORR_OK);
    orr_atomic_abort(&inner);
    orr_output_batch_abort(&batch);
    CHECK(file_equals(final, "picture") && count_entries(tmpdir) == 1);
    remove_tree(tmpdir);
}

/* The name a temporary of process pid would have, from one of ours. */
static void temp_name_of(const char *ours, long pid, char *out, size_t size)
{
    const char *tag = strstr(ours, ORR_TEMP_PREFIX) + strlen(ORR_TEMP_PREFIX); /* HOST-PID-N-NAME */
    const char *rest = strchr(strchr(tag, '-') + 1, '-');                      /* -N-NAME */
    snprintf(out, size, "%.*s%ld%s", (int)(strchr(tag, '-') + 1 - ours), ours, pid, rest);
}

/* A fresh tmpdir with a temporary of this process in it, for frame.png. */
static void begin_own_temporary(orr_atomic_file *af)
{
    make_tmpdir();
    char final[512];
    snprintf(final, sizeof final, "%s/frame.png", tmpdir);
    orr_error err;
    CHECK(orr_atomic_begin(af, final, &err) == ORR_OK);
}

/* A child process that exits at once (the caller reaps it). */
static pid_t exiting_child(void)
{
    pid_t child = fork();
    if (child == 0)
        _exit(0);
    return child;
}

/* A killed run's temporaries are removed by the next; a running one's, or
 * another host's, are kept. */
static void test_stale_temporaries(void)
{
    char dead[600], alive[600], other_host[600], other[600];
    orr_atomic_file af;
    begin_own_temporary(&af);
    pid_t child = exiting_child();
    waitpid(child, NULL, 0); /* a process that is gone */
    temp_name_of(af.temp_path, (long)child, dead, sizeof dead);
    temp_name_of(af.temp_path, (long)getppid(), alive, sizeof alive);
    write_text(dead, "19 GB of a killed render");
    write_text(alive, "another run, still going");
    snprintf(other_host, sizeof other_host, "%s/" ORR_TEMP_PREFIX "00000000-%ld-0-x.png", tmpdir, (long)child);
    if (strstr(dead, ORR_TEMP_PREFIX "00000000-"))
        other_host[strlen(tmpdir) + 1 + strlen(ORR_TEMP_PREFIX)] = '1'; /* never this host's tag */
    write_text(other_host, "a shared folder's");
    snprintf(other, sizeof other, "%s/.frame.png.tmp-AbC123", tmpdir);
    write_text(other, "not named like ours");
    CHECK(orr_remove_stale_temporaries(tmpdir) == 1);
    CHECK(!exists(dead) && exists(alive) && exists(other_host) && exists(other));
    CHECK(exists(af.temp_path)); /* this process's own */
    orr_atomic_abort(&af);
    remove_tree(tmpdir);
}

/* A job process killed with its run is a zombie until reaped, which
 * kill(pid, 0) takes for alive: its temporaries are stale all the same. */
static void test_zombie_temporaries(void)
{
    char zombie_temp[600];
    orr_atomic_file af;
    begin_own_temporary(&af);
    pid_t child = exiting_child();
    /* Not reaped: wait until it has exited and is a zombie. */
    siginfo_t info;
    memset(&info, 0, sizeof info);
    CHECK(waitid(P_PID, (id_t)child, &info, WEXITED | WNOWAIT) == 0);
    temp_name_of(af.temp_path, (long)child, zombie_temp, sizeof zombie_temp);
    write_text(zombie_temp, "a killed job's frame");
    CHECK(kill(child, 0) == 0); /* what the old check saw: alive */
    CHECK(orr_remove_stale_temporaries(tmpdir) == 1);
    CHECK(!exists(zombie_temp) && exists(af.temp_path));
    waitpid(child, NULL, 0);
    orr_atomic_abort(&af);
    remove_tree(tmpdir);
}

/* What a SIGINT handler does: the open temporaries go, the rest stays. */
static void test_live_temporaries_removed(void)
{
    make_tmpdir();
    char a[512], b[512], done[512];
    snprintf(a, sizeof a, "%s/a.fits", tmpdir);
    snprintf(b, sizeof b, "%s/b.fits", tmpdir);
    snprintf(done, sizeof done, "%s/done.png", tmpdir);
    pid_t child = fork();
    if (child == 0) {
        orr_atomic_file fa, fb, fd;
        orr_error err;
        if (orr_atomic_begin(&fd, done, &err) || orr_atomic_commit(&fd, &err) || orr_atomic_begin(&fa, a, &err) ||
            orr_atomic_begin(&fb, b, &err))
            _exit(2);
        orr_remove_live_temporaries();
        _exit(0);
    }
    int status = -1;
    waitpid(child, &status, 0);
    CHECK(WIFEXITED(status) && WEXITSTATUS(status) == 0);
    CHECK(count_entries(tmpdir) == 1 && exists(done));
    remove_tree(tmpdir);
}

static void test_check_output_dir(void)
{
    make_tmpdir();
    orr_error err;
    char dir[512], deep[600], file[512], under_file[600];
    /* existing folder: fine, and the probe file is gone again */
    CHECK(orr_check_output_dir(tmpdir, &err) == ORR_OK);
    CHECK(count_entries(tmpdir) == 0);
    /* one missing level is created */
    snprintf(dir, sizeof dir, "%s/frames", tmpdir);
    CHECK(orr_check_output_dir(dir, &err) == ORR_OK);
    struct stat st;
    CHECK(stat(dir, &st) == 0 && S_ISDIR(st.st_mode));
    CHECK(count_entries(dir) == 0);
    /* several missing levels are created too, like mkdir -p */
    snprintf(deep, sizeof deep, "%s/missing/frames", tmpdir);
    orr_error_clear(&err);
    CHECK(orr_check_output_dir(deep, &err) == ORR_OK);
    CHECK(stat(deep, &st) == 0 && S_ISDIR(st.st_mode));
    CHECK(count_entries(deep) == 0);
    /* a regular file where the folder should be, and a folder below one */
    snprintf(file, sizeof file, "%s/regular", tmpdir);
    write_text(file, "x");
    orr_error_clear(&err);
    CHECK(orr_check_output_dir(file, &err) == ORR_ERR_IO);
    CHECK_CONTAINS(err.msg, file);
    CHECK_CONTAINS(err.msg, "not a directory");
    snprintf(under_file, sizeof under_file, "%s/sub", file);
    orr_error_clear(&err);
    CHECK(orr_check_output_dir(under_file, &err) == ORR_ERR_IO);
    CHECK_CONTAINS(err.msg, "output directory");
    CHECK_CONTAINS(err.msg, under_file);
    CHECK_CONTAINS(err.msg, strerror(ENOTDIR));
    CHECK(file_equals(file, "x"));
    CHECK(count_entries(tmpdir) == 3); /* frames, missing and regular */
    remove_tree(tmpdir);
}

int main(void)
{
    RUN(test_commit_renames_and_leaves_no_temp);
    RUN(test_abort_keeps_old_file);
    RUN(test_abort_creates_nothing);
    RUN(test_relative_name_without_folder);
    RUN(test_begin_fails_in_unwritable_folder);
    RUN(test_failed_commit_removes_temp);
    RUN(test_check_output_dir);
    RUN(test_batch_all_or_nothing);
    RUN(test_no_temporary_of_a_temporary);
    RUN(test_stale_temporaries);
    RUN(test_zombie_temporaries);
    RUN(test_live_temporaries_removed);
    return check_summary();
}
