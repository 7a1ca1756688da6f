/* A source dealt out among processes: the parts together see every
 * particle exactly once, whether chunks are skipped (the model) or read and
 * dropped (a text table). */
#include <stdio.h>
#include <stdlib.h>

#include "check.h"
#include "source/models/model.h"
#include "source/partition.h"
#include "tmpdir.h"

static orr_source *open_model(size_t chunk)
{
    orr_model_params mp = {10007, 3, 780, ORR_MODEL_PAIR, 0, 0, 0, 0};
    orr_source *src = NULL;
    orr_error err = {0};
    CHECK(orr_model_source_open(&mp, chunk, &src, &err) == ORR_OK);
    return src;
}

static orr_source *open_table(const char *path, size_t chunk)
{
    orr_source_options opt = {.format = "auto", .chunk_size = chunk};
    orr_source *src = NULL;
    orr_error err = {0};
    CHECK(orr_source_open_file(path, &opt, &src, &err) == ORR_OK);
    return src;
}

/* Reads every part of a source, twice (rewound), counting how often each id comes. */
static void check_parts(orr_source *(*open)(const void *), const void *arg, uint64_t total, int nparts)
{
    unsigned char *seen = calloc(total + 1, 1);
    for (int part = 0; part < nparts; part++) {
        orr_source *src;
        orr_error err = {0};
        CHECK(orr_source_partition(open(arg), part, nparts, &src, &err) == ORR_OK);
        for (int pass = 0; pass < 2; pass++) {
            const orr_chunk *c;
            while (orr_source_next(src, &c, &err) == ORR_OK && c->n > 0)
                for (size_t i = 0; i < c->n; i++)
                    if (pass == 0 && c->id[i] <= total)
                        seen[c->id[i]]++;
            CHECK(orr_source_rewind(src, &err) == ORR_OK);
        }
        orr_source_close(src);
    }
    int once = 1;
    for (uint64_t id = 1; id <= total; id++)
        once &= seen[id] == 1;
    CHECK(once);
    free(seen);
}

static orr_source *model_opener(const void *arg) { return open_model(*(const size_t *)arg); }
static orr_source *table_opener(const void *arg) { return open_table(arg, 7); }

int main(void)
{
    size_t chunks[] = {1000, 4096, 20000};
    for (int k = 0; k < 3; k++)
        for (int nparts = 1; nparts <= 4; nparts++)
            check_parts(model_opener, &chunks[k], 10007, nparts);

    make_tmpdir();
    char path[512];
    snprintf(path, sizeof path, "%s/t.txt", tmpdir);
    FILE *f = fopen(path, "w");
    fprintf(f, "x y z mass id\n");
    for (int i = 1; i <= 100; i++)
        fprintf(f, "%d 0 0 1 %d\n", i, i);
    fclose(f);
    for (int nparts = 1; nparts <= 5; nparts++)
        check_parts(table_opener, path, 100, nparts);

    /* A model chunk of part 1 of 3 is the inner source's second chunk. */
    orr_source *src;
    orr_error err = {0};
    CHECK(orr_source_partition(open_model(1000), 1, 3, &src, &err) == ORR_OK);
    const orr_chunk *c;
    CHECK(orr_source_next(src, &c, &err) == ORR_OK && c->n == 1000 && c->first_index == 1000);
    CHECK(orr_source_next(src, &c, &err) == ORR_OK && c->first_index == 4000);
    orr_source_close(src);
    CHECK(orr_source_partition(open_model(1000), 3, 3, &src, &err) == ORR_ERR_USAGE);
    remove_tmpdir();
    return check_summary();
}
