/* The .npy reader's two ways to get rows: read a block at a time with
 * fread into a buffer (streamed), or memory-map the file and decode the rows
 * where they are (mapped), side by side with a plain read() of the file
 * into a 1 MiB buffer (what `cat FILE > /dev/null` does: the I/O floor).
 *
 *   bench_npy_read [PARTICLES [DIR]]     default 5e6 particles in /tmp
 *
 * Writes two files (a structured array x, y, z, mass of float32, and a
 * plain (N, 3) float64 array), then reads each best of five rounds, the
 * three ways alternating, after a first read that fills the page cache: the
 * figures compare the readers' work on cached data, not the disk. */
#include <fcntl.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "clocks.h"
#include "source/readers/npy_reader.h"
#include "source/source.h"

/* An .npy version 1 header for descr, padded to 64 bytes as numpy does. */
static void write_header(FILE *fp, const char *descr, const char *shape)
{
    char dict[256];
    int n = snprintf(dict, sizeof dict, "{'descr': %s, 'fortran_order': False, 'shape': %s, }", descr, shape);
    int total = 10 + n + 1;
    int pad = (64 - total % 64) % 64;
    unsigned short len = (unsigned short)(n + pad + 1);
    fwrite("\x93NUMPY\x01\x00", 1, 8, fp);
    fputc(len & 0xff, fp);
    fputc(len >> 8, fp);
    fwrite(dict, 1, (size_t)n, fp);
    for (int i = 0; i < pad; i++)
        fputc(' ', fp);
    fputc('\n', fp);
}

static double value(uint64_t i, int k) { return (double)((i * 2654435761u + (uint64_t)k * 40503u) % 100000u) * 1e-3; }

static void write_files(const char *structured, const char *plain, long n)
{
    char shape[64];
    snprintf(shape, sizeof shape, "(%ld,)", n);
    FILE *a = fopen(structured, "wb");
    snprintf(shape, sizeof shape, "(%ld,)", n);
    write_header(a, "[('x', '<f4'), ('y', '<f4'), ('z', '<f4'), ('mass', '<f4')]", shape);
    snprintf(shape, sizeof shape, "(%ld, 3)", n);
    FILE *b = fopen(plain, "wb");
    write_header(b, "'<f8'", shape);
    for (long i = 0; i < n; i++) {
        float r[4] = {(float)value((uint64_t)i, 0), (float)value((uint64_t)i, 1), (float)value((uint64_t)i, 2), 1.0f};
        double p[3] = {value((uint64_t)i, 0), value((uint64_t)i, 1), value((uint64_t)i, 2)};
        fwrite(r, sizeof r, 1, a);
        fwrite(p, sizeof p, 1, b);
    }
    fclose(a);
    fclose(b);
}

/* The CPU seconds of the last timed read (on a shared machine, what the
 * work cost, whatever the wall clock says). */
static double last_cpu;

static double plain_read(const char *path, double *mib)
{
    static char buf[1 << 20];
    double t = wall_seconds(), c = cpu_seconds();
    int fd = open(path, O_RDONLY);
    ssize_t got;
    double bytes = 0;
    while ((got = read(fd, buf, sizeof buf)) > 0)
        bytes += (double)got;
    close(fd);
    *mib = bytes / 1048576.0;
    last_cpu = cpu_seconds() - c;
    return wall_seconds() - t;
}

/* Reads every particle as the renderer does; returns the seconds, or -1. */
static double reader_read(const char *path, int mapped, double *checksum)
{
    orr_npy_set_mapping(mapped);
    double t = wall_seconds(), cpu = cpu_seconds();
    orr_source_options opt = {.format = "npy"};
    orr_source *src = NULL;
    orr_error err = {0};
    if (orr_source_open_file(path, &opt, &src, &err) != ORR_OK) {
        fprintf(stderr, "%s\n", err.msg);
        return -1;
    }
    const orr_chunk *c;
    double sum = 0;
    while (orr_source_next(src, &c, &err) == ORR_OK && c->n > 0)
        sum += c->x[c->n - 1] + c->mass[0];
    orr_source_close(src);
    *checksum = sum;
    last_cpu = cpu_seconds() - cpu;
    return wall_seconds() - t;
}

#define ROUNDS 5

static void compare(const char *name, const char *path)
{
    double mib, best[3] = {1e30, 1e30, 1e30}, best_cpu[3] = {1e30, 1e30, 1e30}, sums[2];
    reader_read(path, 0, &sums[0]); /* fills the page cache */
    for (int round = 0; round < ROUNDS; round++)
        for (int k = 0; k < 3; k++) {
            double t = k == 0 ? plain_read(path, &mib) : reader_read(path, k == 2, &sums[k - 1]);
            best[k] = t < best[k] ? t : best[k];
            best_cpu[k] = last_cpu < best_cpu[k] ? last_cpu : best_cpu[k];
        }
    static const char *const way[3] = {"read()", "streamed", "mapped"};
    printf("%s, %.0f MiB%s\n", name, mib, sums[0] == sums[1] ? "" : "  CHECKSUMS DIFFER");
    for (int k = 0; k < 3; k++)
        printf("  %-9s wall %.3f s (%5.0f MiB/s)  cpu %.3f s (%5.0f MiB/s)\n", way[k], best[k], mib / best[k],
               best_cpu[k], mib / best_cpu[k]);
}

int main(int argc, char **argv)
{
    long n = argc > 1 ? (long)strtod(argv[1], NULL) : 5000000;
    const char *dir = argc > 2 ? argv[2] : "/tmp";
    char structured[4096], plain[4096];
    snprintf(structured, sizeof structured, "%s/bench_npy_struct_%ld.npy", dir, (long)getpid());
    snprintf(plain, sizeof plain, "%s/bench_npy_plain_%ld.npy", dir, (long)getpid());
    write_files(structured, plain, n);
    printf("%ld particles, best of %d (page cache warm)\n", n, ROUNDS);
    compare("structured x,y,z,mass float32", structured);
    compare("plain (N, 3) float64", plain);
    unlink(structured);
    unlink(plain);
    return 0;
}
