/* The plain-text particle reader: good tables in their variants, chunking,
 * rewinding, and each kind of bad table with its message. */
#include <fcntl.h>
#include <stdlib.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "check.h"
#include "source/readers/text_reader.h"
#include "source/source.h"

static char tmpdir[] = "/tmp/orrery-text-XXXXXX";

static const char *write_file(const char *name, const char *text)
{
    static char path[512];
    snprintf(path, sizeof path, "%s/%s", tmpdir, name);
    FILE *fp = fopen(path, "w");
    fputs(text, fp);
    fclose(fp);
    return path;
}

/* Opens path, reads everything into one chunk's worth of checks via cb. */
static orr_status open_text(const char *path, size_t chunk, orr_source **src, orr_error *err)
{
    orr_source_options opt = {.format = "text", .chunk_size = chunk};
    return orr_source_open_file(path, &opt, src, err);
}

static void test_whitespace_table_with_all_columns(void)
{
    const char *path = write_file("good.txt",
                                  "x y z mass h id type temp\n"
                                  "1 2 3 0.5 0.1 42 2 5800\n"
                                  "# a comment between rows\n"
                                  "\n"
                                  "-1.5e2 0 1e-3 2 0.2 18446744073709551615 5 3000\n");
    orr_source *src;
    orr_error err = {0};
    CHECK(open_text(path, 100, &src, &err) == ORR_OK);
    CHECK(src->info.has_h && src->info.has_id && src->info.has_type);
    CHECK(src->info.nextra == 1 && strcmp(src->info.extra_names[0], "temp") == 0);
    const orr_chunk *c;
    CHECK(orr_source_next(src, &c, &err) == ORR_OK);
    CHECK(c->n == 2);
    CHECK(c->x[0] == 1.0f && c->y[0] == 2.0f && c->z[0] == 3.0f && c->mass[0] == 0.5f && c->h[0] == 0.1f);
    CHECK(c->id[0] == 42 && c->type[0] == 2);
    CHECK(c->x[1] == -150.0f && c->z[1] == 1e-3f && c->id[1] == UINT64_MAX && c->type[1] == 5);
    CHECK(orr_chunk_field(c, "temp")[1] == 3000.0f);
    CHECK(orr_source_next(src, &c, &err) == ORR_OK && c->n == 0);
    orr_source_close(src);
}

static void test_comma_table_defaults_and_hash_header(void)
{
    const char *path = write_file("comma.csv", "# x, y, z\n0.5,1.5,2.5\n 3 , 4 , 5 \n");
    orr_source *src;
    orr_error err = {0};
    CHECK(open_text(path, 10, &src, &err) == ORR_OK);
    CHECK(!src->info.has_h && !src->info.has_id);
    const orr_chunk *c;
    CHECK(orr_source_next(src, &c, &err) == ORR_OK && c->n == 2);
    /* No mass column: unit masses; no id column: row numbers from 0. */
    CHECK(c->mass[0] == 1.0f && c->mass[1] == 1.0f);
    CHECK(c->id[0] == 0 && c->id[1] == 1);
    CHECK(c->x[1] == 3.0f && c->z[1] == 5.0f);
    CHECK(c->h == NULL);
    orr_source_close(src);
}

static void test_chunks_and_rewind(void)
{
    char text[4096] = "x y z m\n";
    for (int i = 0; i < 10; i++)
        snprintf(text + strlen(text), sizeof text - strlen(text), "%d 0 0 %d\n", i, i + 1);
    const char *path = write_file("ten.txt", text);
    orr_source *src;
    orr_error err = {0};
    CHECK(open_text(path, 3, &src, &err) == ORR_OK);
    for (int pass = 0; pass < 2; pass++) {
        size_t total = 0, chunks = 0;
        double mass = 0;
        const orr_chunk *c;
        while (orr_source_next(src, &c, &err) == ORR_OK && c->n > 0) {
            CHECK(c->first_index == total);
            CHECK(c->x[0] == (float)total);
            for (size_t i = 0; i < c->n; i++)
                mass += c->mass[i];
            total += c->n;
            chunks++;
        }
        CHECK(total == 10 && chunks == 4);
        CHECK_NEAR(mass, 55, 0);
        CHECK(orr_source_rewind(src, &err) == ORR_OK);
    }
    orr_source_close(src);
}

/* Reads all of a table and returns the status of the first failure. */
static orr_status read_all(const char *name, const char *text, orr_error *err)
{
    const char *path = write_file(name, text);
    orr_source *src;
    orr_status st = open_text(path, 4, &src, err);
    if (st)
        return st;
    const orr_chunk *c;
    while (!(st = orr_source_next(src, &c, err)) && c->n > 0) {
    }
    orr_source_close(src);
    return st;
}

static void test_bad_tables(void)
{
    orr_error err = {0};
    CHECK(read_all("short.txt", "x y z mass\n1 2 3 4\n1 2 3\n", &err) == ORR_ERR_FORMAT);
    CHECK_CONTAINS(err.msg, "short.txt:3: row has 3 values; the header (line 1) names 4 columns");
    CHECK(read_all("long.txt", "x y z\n1 2 3 4\n", &err) == ORR_ERR_FORMAT);
    CHECK_CONTAINS(err.msg, "long.txt:2: row has more than 3 values");
    CHECK(read_all("nan.txt", "x y z mass\n1 2 3 4\n1 2 abc 4\n", &err) == ORR_ERR_FORMAT);
    CHECK_CONTAINS(err.msg, "nan.txt:3: column 'z': 'abc' is not a number");
    CHECK(read_all("noz.txt", "x y mass\n1 2 3\n", &err) == ORR_ERR_FORMAT);
    CHECK_CONTAINS(err.msg, "noz.txt:1: the header has no 'z' column");
    CHECK(read_all("numhdr.txt", "1 2 3\n4 5 6\n", &err) == ORR_ERR_FORMAT);
    CHECK_CONTAINS(err.msg, "column 1 name '1' is not a name");
    CHECK(read_all("dup.txt", "x y z x\n", &err) == ORR_ERR_FORMAT);
    CHECK_CONTAINS(err.msg, "column 'x' is named twice");
    CHECK(read_all("empty.txt", "\n\n", &err) == ORR_ERR_FORMAT);
    CHECK_CONTAINS(err.msg, "empty.txt: no header line");
    CHECK(read_all("negmass.txt", "x y z mass\n1 2 3 -4\n", &err) == ORR_ERR_FORMAT);
    CHECK_CONTAINS(err.msg, "negmass.txt:2: column 'mass': particle 0: mass -4 is negative");
    CHECK(read_all("badid.txt", "x y z id\n1 2 3 7.5\n", &err) == ORR_ERR_FORMAT);
    CHECK_CONTAINS(err.msg, "badid.txt:2: column 'id': '7.5'");
    CHECK(read_all("badtype.txt", "x y z type\n1 2 3 6\n", &err) == ORR_ERR_FORMAT);
    CHECK_CONTAINS(err.msg, "badtype.txt:2: column 'type': 6");
    /* NaN positions are read as they are: the renderer applies input.nonfinite. */
    CHECK(read_all("nanpos.txt", "x y z\nnan 0 0\ninf 1 1\n", &err) == ORR_OK);
}

/* The mass policy every reader shares (docs/input.md): negative, non-finite
 * and float-unrepresentable masses are errors naming file, line, particle
 * and value; 0 and tiny but representable masses are read. */
static void test_mass_policy(void)
{
    static const struct {
        const char *value, *needle;
    } bad[] = {
        {"nan", "particle 1: mass nan is not a finite number"},
        {"-inf", "particle 1: mass -inf is not a finite number"},
        {"-1e-3", "particle 1: mass -1e-3 is negative"},
        {"1e-300", "particle 1: mass 1e-300 is too small for a float (it would become 0"},
        {"1e39", "particle 1: mass 1e39 is too large for a float"},
    };
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
        char text[128];
        snprintf(text, sizeof text, "x y z mass\n1 2 3 4\n# a comment\n1 2 3 %s\n", bad[k].value);
        orr_error err = {0};
        CHECK(read_all("masses.txt", text, &err) == ORR_ERR_FORMAT);
        CHECK_CONTAINS(err.msg, "masses.txt:4: column 'mass': ");
        CHECK_CONTAINS(err.msg, bad[k].needle);
    }
    orr_error err = {0};
    CHECK(read_all("goodmasses.txt", "x y z mass\n1 2 3 0\n1 2 3 1e-40\n1 2 3 -0\n", &err) == ORR_OK);
}

/* A table of n rows, mass = row number, in buf. */
static size_t make_table(char *buf, size_t size, int n)
{
    size_t len = (size_t)snprintf(buf, size, "x y z mass\n");
    for (int i = 0; i < n && len < size; i++)
        len += (size_t)snprintf(buf + len, size - len, "%d.125 -%d.5 0.25 %d\n", i, i, i);
    return len;
}

/* Reads a source to its end: the rows and the sum of their masses. */
static orr_status count_rows(orr_source *src, long *rows, double *mass, orr_error *err)
{
    const orr_chunk *c;
    orr_status st;
    *rows = 0;
    *mass = 0;
    while (!(st = orr_source_next(src, &c, err)) && c->n > 0)
        for (size_t i = 0; i < c->n; i++, (*rows)++)
            *mass += c->mass[i];
    return st;
}

/* A stream is read once: the bytes format detection took (here the first
 * head bytes, cut inside a row) are read first, then the rest. */
static void test_stream_reads_peeked_bytes_first(void)
{
    static char table[65536];
    size_t len = make_table(table, sizeof table, 1000);
    const size_t cuts[] = {0, 5, 11, 37, 4096, len};
    for (size_t k = 0; k < sizeof cuts / sizeof cuts[0]; k++) {
        size_t head = cuts[k];
        FILE *rest = fmemopen(table + head, len - head + 1, "r");
        orr_source_options opt = {.chunk_size = 64};
        orr_source *src = NULL;
        orr_error err = {0};
        CHECK(orr_text_source_open_stream("a pipe", rest, 1, (const unsigned char *)table, head, &opt, &src, &err) ==
              ORR_OK);
        if (!src)
            continue;
        long rows;
        double mass;
        CHECK(count_rows(src, &rows, &mass, &err) == ORR_OK);
        CHECK(rows == 1000 && mass == 999.0 * 1000 / 2);
        CHECK(orr_source_rewind(src, &err) == ORR_ERR_USAGE);
        CHECK_CONTAINS(err.msg, "a pipe: this scene reads its particles twice, but a pipe can be read only once");
        orr_source_close(src);
    }
}

/* A FIFO no program writes to: opening it used to wait for a writer
 * forever; now it reads as empty at once (and binary formats are refused
 * before opening). The alarm turns a hang into a failure. */
static void test_fifo_without_writer(void)
{
    char fifo[512];
    snprintf(fifo, sizeof fifo, "%s/nowriter", tmpdir);
    CHECK(mkfifo(fifo, 0600) == 0);
    alarm(20);
    orr_source_options opt = {.format = "auto", .chunk_size = 16};
    orr_source *src = NULL;
    orr_error err = {0};
    CHECK(orr_source_open_file(fifo, &opt, &src, &err) == ORR_ERR_FORMAT && src == NULL);
    CHECK_CONTAINS(err.msg, "nowriter: no data (a pipe or FIFO): no program had it open for writing");
    const char *const binary[] = {"gadget", "hdf5", "tipsy"};
    for (int k = 0; k < 3; k++) {
        opt.format = binary[k];
        CHECK(orr_source_open_file(fifo, &opt, &src, &err) == ORR_ERR_USAGE && src == NULL);
        CHECK_CONTAINS(err.msg, "nowriter: ");
        CHECK_CONTAINS(err.msg, " files are read with seeks, so the input must be a regular file, but this is a "
                                "pipe or FIFO");
    }
    alarm(0);
}

/* A FIFO whose writer is there: read once, the format detected from the
 * bytes kept for the reader, not lost. The child holds the FIFO open (read
 * and write, which does not wait) before the parent opens it, and closes it
 * (ending the parent's input) only once the parent has opened it, so no
 * timing is involved. */
static void test_fifo_with_writer(void)
{
    static char table[65536];
    size_t len = make_table(table, sizeof table, 700);
    char fifo[512];
    snprintf(fifo, sizeof fifo, "%s/writer", tmpdir);
    CHECK(mkfifo(fifo, 0600) == 0);
    int ready[2], opened[2];
    CHECK(pipe(ready) == 0 && pipe(opened) == 0);
    alarm(20);
    pid_t pid = fork();
    if (pid == 0) {
        int fd = open(fifo, O_RDWR);
        char c = 1;
        if (fd < 0 || write(ready[1], &c, 1) != 1)
            _exit(1);
        /* The parent reads as this writes; closing ends its input. */
        size_t done = 0;
        while (done < len) {
            ssize_t w = write(fd, table + done, len - done);
            if (w <= 0)
                _exit(1);
            done += (size_t)w;
        }
        if (read(opened[0], &c, 1) != 1)
            _exit(1);
        close(fd);
        _exit(0);
    }
    char c = 0;
    CHECK(read(ready[0], &c, 1) == 1);
    orr_source_options opt = {.format = "auto", .chunk_size = 50};
    orr_source *src = NULL;
    orr_error err = {0};
    CHECK(orr_source_open_file(fifo, &opt, &src, &err) == ORR_OK);
    CHECK(write(opened[1], &c, 1) == 1);
    if (src) {
        long rows = 0;
        double mass = 0;
        CHECK(count_rows(src, &rows, &mass, &err) == ORR_OK);
        CHECK(rows == 700 && mass == 699.0 * 700 / 2);
        CHECK(strcmp(src->info.format, "text") == 0);
        orr_source_close(src);
    } else {
        fprintf(stderr, "  %s\n", err.msg);
    }
    int status = 0;
    waitpid(pid, &status, 0);
    CHECK(WIFEXITED(status) && WEXITSTATUS(status) == 0);
    close(ready[0]);
    close(ready[1]);
    close(opened[0]);
    close(opened[1]);
    alarm(0);
}

static void test_missing_file(void)
{
    orr_source *src;
    orr_error err = {0};
    CHECK(open_text("/nonexistent/particles.txt", 10, &src, &err) == ORR_ERR_IO);
    CHECK_CONTAINS(err.msg, "/nonexistent/particles.txt: cannot open: No such file or directory");
    CHECK(src == NULL);
    orr_source_options opt = {.format = "gadget9", .chunk_size = 10};
    CHECK(orr_source_open_file("x.bin", &opt, &src, &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "unknown input format 'gadget9'");
    /* A directory opens but cannot be read. */
    CHECK(open_text(tmpdir, 10, &src, &err) != ORR_OK);
    CHECK_CONTAINS(err.msg, tmpdir);
}

static void test_format_detection(void)
{
    orr_source *src;
    orr_error err = {0};
    orr_source_options opt = {.format = "auto", .chunk_size = 10};
    const char *text = write_file("auto.txt", "x y z\n1 2 3\n");
    CHECK(orr_source_open_file(text, &opt, &src, &err) == ORR_OK);
    CHECK(src && strcmp(src->info.format, "text") == 0);
    orr_source_close(src);
    /* Binary bytes are not text: auto detection names the file and the formats. */
    const char *bin = write_file("binary.dat", "x y z\n");
    FILE *fp = fopen(bin, "ab");
    fputc(0, fp);
    fputc(7, fp);
    fclose(fp);
    CHECK(orr_source_open_file(bin, &opt, &src, &err) == ORR_ERR_FORMAT);
    CHECK_CONTAINS(err.msg, "binary.dat: not a particle file orrery recognises");
    CHECK(orr_source_open_file("/nonexistent.dat", &opt, &src, &err) == ORR_ERR_IO);
    CHECK_CONTAINS(err.msg, "/nonexistent.dat: cannot open");
}

int main(void)
{
    if (!mkdtemp(tmpdir)) {
        perror("mkdtemp");
        return 1;
    }
    RUN(test_whitespace_table_with_all_columns);
    RUN(test_comma_table_defaults_and_hash_header);
    RUN(test_chunks_and_rewind);
    RUN(test_bad_tables);
    RUN(test_mass_policy);
    RUN(test_stream_reads_peeked_bytes_first);
    RUN(test_fifo_without_writer);
    RUN(test_fifo_with_writer);
    RUN(test_missing_file);
    RUN(test_format_detection);
    char cmd[600];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", tmpdir);
    if (system(cmd) != 0)
        fprintf(stderr, "could not remove %s\n", tmpdir);
    return check_summary();
}
