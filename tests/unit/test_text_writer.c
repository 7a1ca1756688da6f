/* Tests of the text table writer: the model written to a file and read back
 * with plain stdio (and with the text reader) gives the same floats bit for
 * bit; failures leave no file behind. */
#include <dirent.h>
#include <errno.h>
#include <signal.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <unistd.h>

#include "check.h"
#include "source/models/model.h"
#include "source/readers/text_reader.h"
#include "source/writers/text_writer.h"

static char tmpdir[256];

static void make_tmpdir(void)
{
    snprintf(tmpdir, sizeof tmpdir, "/tmp/orr_test_text_writer_XXXXXX");
    if (!mkdtemp(tmpdir)) {
        fprintf(stderr, "mkdtemp: %s\n", strerror(errno));
        exit(1);
    }
}

/* Files in the temporary folder other than "." and "..". */
static int count_files(void)
{
    DIR *d = opendir(tmpdir);
    int n = 0;
    if (!d)
        return -1;
    for (struct dirent *e; (e = readdir(d));)
        n += strcmp(e->d_name, ".") != 0 && strcmp(e->d_name, "..") != 0;
    closedir(d);
    return n;
}

static void remove_tmpdir(void)
{
    DIR *d = opendir(tmpdir);
    if (d) {
        char p[512];
        for (struct dirent *e; (e = readdir(d));) {
            if (strcmp(e->d_name, ".") == 0 || strcmp(e->d_name, "..") == 0)
                continue;
            snprintf(p, sizeof p, "%s/%s", tmpdir, e->d_name);
            unlink(p);
        }
        closedir(d);
    }
    rmdir(tmpdir);
}

static orr_source *open_model(long long n, size_t chunk)
{
    orr_model_params p = {n, 2024, 780.0, ORR_MODEL_PAIR, 0, 0, 0, 0};
    orr_source *src = NULL;
    orr_error err = {0};
    if (orr_model_source_open(&p, chunk, &src, &err) != ORR_OK)
        fprintf(stderr, "model: %s\n", err.msg);
    return src;
}

static int same_float(float a, float b)
{
    return memcmp(&a, &b, sizeof a) == 0;
}

/* Parses one data row (x y z mass id type and c's extra fields) and
 * compares it with particle i of c. */
static int row_matches(char *line, const orr_chunk *c, size_t i)
{
    char *tok[6 + ORR_MAX_EXTRA_FIELDS + 1];
    int n = 0;
    for (char *s = strtok(line, " \n"); s && n < 6 + ORR_MAX_EXTRA_FIELDS + 1; s = strtok(NULL, " \n"))
        tok[n++] = s;
    if (n != 6 + c->nextra)
        return 0;
    const float want[4] = {c->x[i], c->y[i], c->z[i], c->mass[i]};
    for (int k = 0; k < 4; k++)
        if (!same_float(strtof(tok[k], NULL), want[k]))
            return 0;
    if (strtoull(tok[4], NULL, 10) != c->id[i] || strtoul(tok[5], NULL, 10) != c->type[i])
        return 0;
    for (int k = 0; k < c->nextra; k++)
        if (!same_float(strtof(tok[6 + k], NULL), c->extra[k].data[i]))
            return 0;
    return 1;
}

static void test_model_round_trip_stdio(void)
{
    const long long n = 777;
    char path[512];
    snprintf(path, sizeof path, "%s/galaxy.txt", tmpdir);
    orr_source *src = open_model(n, 50);
    orr_error err = {0};
    CHECK(src && orr_text_write_source(src, path, &err) == ORR_OK);
    orr_source_close(src);
    CHECK(count_files() == 1); /* no temporary file left over */

    orr_source *ref = open_model(n, (size_t)n); /* the whole model in one chunk */
    const orr_chunk *c = NULL;
    CHECK(ref && orr_source_next(ref, &c, &err) == ORR_OK && c->n == (size_t)n);
    FILE *f = fopen(path, "r");
    CHECK(f != NULL);
    if (!f || !c) {
        orr_source_close(ref);
        return;
    }
    char line[1024];
    CHECK(fgets(line, sizeof line, f) && strcmp(line, "x y z mass id type vx vy vz r E0 ez\n") == 0);
    size_t rows = 0, good = 0;
    while (fgets(line, sizeof line, f)) {
        if (rows < c->n)
            good += row_matches(line, c, rows);
        rows++;
    }
    CHECK(rows == (size_t)n);
    CHECK(good == (size_t)n);
    fclose(f);
    orr_source_close(ref);
}

/* The lead's text reader reads the file back to the same particles. */
static void test_model_round_trip_reader(void)
{
    const long long n = 300;
    char path[512];
    snprintf(path, sizeof path, "%s/reader.txt", tmpdir);
    orr_source *src = open_model(n, 1000);
    orr_error err = {0};
    CHECK(src && orr_text_write_source(src, path, &err) == ORR_OK);
    orr_source_close(src);

    orr_source *ref = open_model(n, (size_t)n), *back = NULL;
    orr_source_options opt = {.format = "text", .chunk_size = 1000};
    CHECK(orr_text_source_open(path, &opt, &back, &err) == ORR_OK);
    const orr_chunk *a = NULL, *b = NULL;
    if (!ref || !back || orr_source_next(ref, &a, &err) != ORR_OK || orr_source_next(back, &b, &err) != ORR_OK) {
        CHECK(!"reading back failed");
        fprintf(stderr, "%s\n", err.msg);
    } else {
        CHECK(b->n == a->n);
        CHECK(back->info.has_id && back->info.has_type && !back->info.has_h && back->info.nextra == 6);
        size_t fl = a->n * sizeof(float);
        CHECK(b->n == a->n && memcmp(a->x, b->x, fl) == 0 && memcmp(a->y, b->y, fl) == 0 &&
              memcmp(a->z, b->z, fl) == 0 && memcmp(a->mass, b->mass, fl) == 0 &&
              memcmp(a->id, b->id, a->n * sizeof(uint64_t)) == 0 && memcmp(a->type, b->type, a->n) == 0);
        for (int k = 0; k < a->nextra && b->n == a->n; k++) {
            const float *v = orr_chunk_field(b, a->extra[k].name);
            CHECK(v && memcmp(v, a->extra[k].data, fl) == 0);
        }
    }
    orr_source_close(ref);
    orr_source_close(back);
    unlink(path);
}

/* A minimal source for failure cases: two particles with an extra field of
 * a configurable name, failing on the second next() when asked. */
typedef struct fake_state {
    int calls, fail;
} fake_state;

static orr_status fake_next(orr_source *src, orr_error *err)
{
    fake_state *st = src->state;
    if (st->calls++ > 0) {
        if (st->fail)
            return orr_fail(err, ORR_ERR_FORMAT, "fake: broken record");
        return ORR_OK;
    }
    orr_chunk *c = &src->chunk;
    for (size_t i = 0; i < 2; i++) {
        c->x[i] = c->y[i] = c->z[i] = c->mass[i] = c->h[i] = (float)i + 0.1f;
        c->id[i] = i;
        c->type[i] = 0;
        c->extra[0].data[i] = 1e-30f;
    }
    c->n = 2;
    return ORR_OK;
}

static const orr_source_ops FAKE_OPS = {.next = fake_next};

static void fake_open(orr_source *src, fake_state *st, const char *extra, int fail)
{
    memset(src, 0, sizeof *src);
    st->calls = 0;
    st->fail = fail;
    src->ops = &FAKE_OPS;
    src->state = st;
    src->info.has_h = 1;
    src->info.nextra = 1;
    snprintf(src->info.extra_names[0], ORR_FIELD_NAME_MAX, "%s", extra);
    const char *names[1] = {extra};
    orr_error err = {0};
    if (orr_chunk_alloc(&src->chunk, 2, 1, names, 1, &err) != ORR_OK)
        exit(1);
}

static void test_source_error_leaves_no_file(void)
{
    char path[512];
    snprintf(path, sizeof path, "%s/broken.txt", tmpdir);
    orr_source src;
    fake_state st;
    fake_open(&src, &st, "temp", 1);
    orr_error err = {0};
    CHECK(orr_text_write_source(&src, path, &err) == ORR_ERR_FORMAT);
    CHECK_CONTAINS(err.msg, "broken record");
    CHECK(access(path, F_OK) != 0);
    CHECK(count_files() == 1); /* only galaxy.txt from the first test */
    orr_chunk_free(&src.chunk);
}

static void test_with_h_column(void)
{
    char path[512];
    snprintf(path, sizeof path, "%s/with_h.txt", tmpdir);
    orr_source src;
    fake_state st;
    fake_open(&src, &st, "temp", 0);
    orr_error err = {0};
    CHECK(orr_text_write_source(&src, path, &err) == ORR_OK);
    FILE *f = fopen(path, "r");
    char line[256] = "";
    CHECK(f && fgets(line, sizeof line, f) && strcmp(line, "x y z mass h id type temp\n") == 0);
    CHECK(f && fgets(line, sizeof line, f) && strcmp(line, "0.100000001 0.100000001 0.100000001 0.100000001 "
                                                           "0.100000001 0 0 1e-30\n") == 0);
    if (f)
        fclose(f);
    unlink(path);
    orr_chunk_free(&src.chunk);
}

static void test_bad_names_and_paths(void)
{
    char path[512];
    snprintf(path, sizeof path, "%s/bad.txt", tmpdir);
    orr_source src;
    fake_state st;
    fake_open(&src, &st, "mass", 0); /* would be read back as the mass */
    orr_error err = {0};
    CHECK(orr_text_write_source(&src, path, &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "'mass'");
    CHECK(access(path, F_OK) != 0);
    orr_chunk_free(&src.chunk);

    fake_open(&src, &st, "temp", 0);
    snprintf(path, sizeof path, "%s/no/such/dir/out.txt", tmpdir);
    CHECK(orr_text_write_source(&src, path, &err) == ORR_ERR_IO);
    CHECK_CONTAINS(err.msg, "no/such/dir");
    orr_chunk_free(&src.chunk);
}

/* A write error part-way (here: the file size limit, which fails write()
 * with EFBIG the way a full disk fails it with ENOSPC) is reported naming
 * the file, and no file is left behind. */
static void test_write_error_midway(void)
{
    struct rlimit old, small;
    if (getrlimit(RLIMIT_FSIZE, &old) != 0)
        return;
    char path[512];
    snprintf(path, sizeof path, "%s/too_big.txt", tmpdir);
    orr_source *src = open_model(100000, 4096); /* ~8 MB of text */
    void (*old_handler)(int) = signal(SIGXFSZ, SIG_IGN);
    small = old;
    small.rlim_cur = 1 << 20;
    CHECK(setrlimit(RLIMIT_FSIZE, &small) == 0);
    orr_error err = {0};
    orr_status st = src ? orr_text_write_source(src, path, &err) : ORR_ERR_INTERNAL;
    setrlimit(RLIMIT_FSIZE, &old);
    signal(SIGXFSZ, old_handler);
    CHECK(st == ORR_ERR_IO);
    CHECK_CONTAINS(err.msg, path);
    CHECK(access(path, F_OK) != 0);
    CHECK(count_files() == 1); /* only galaxy.txt from the first test */
    orr_source_close(src);
}

int main(void)
{
    make_tmpdir();
    RUN(test_model_round_trip_stdio);
    RUN(test_model_round_trip_reader);
    RUN(test_source_error_leaves_no_file);
    RUN(test_with_h_column);
    RUN(test_bad_names_and_paths);
    RUN(test_write_error_midway);
    remove_tmpdir();
    return check_summary();
}
