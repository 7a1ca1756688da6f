/* Streaming benchmark for the Gadget reader.
 *
 *   bench_gadget_stream --generate FILE --particles 1e8   write FILE, then read it
 *   bench_gadget_stream --read FILE                       read an existing snapshot
 *
 * --generate writes a SnapFormat 2, little-endian, float, 32-bit-id snapshot
 * of dark-matter particles (type 1, mass from the header) with the test-only
 * writer, which streams, so generating holds no particles in memory. Reading
 * is timed twice: a plain read() of the file into a 1 MiB buffer (what `cat
 * FILE > /dev/null` does: the I/O floor), then the reader yielding every
 * chunk with positions and mass only, as the renderer asks. The plain read
 * goes first, so both run with whatever the page cache holds after it. */
#include <errno.h>
#include <fcntl.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "gadget_writer.h"
#include "source/readers/gadget.h"
#include "source/source.h"
#include "clocks.h"

#define MAX_PER_TYPE 2147483647LL

static double peak_rss_mib(void)
{
    struct rusage ru;
    getrusage(RUSAGE_SELF, &ru);
    return (double)ru.ru_maxrss / 1024.0; /* Linux: kilobytes */
}

static uint64_t mix(uint64_t z)
{
    z += 0x9e3779b97f4a7c15ull;
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

/* Particle i: uniform in a 100-unit box, small random velocities. */
static void generate_particle(void *user, uint64_t i, int type, gw_particle *p)
{
    (void)user;
    (void)type;
    uint64_t r = mix(i);
    for (int k = 0; k < 3; k++) {
        p->pos[k] = (double)((r >> (21 * k)) & 0x1fffff) * (100.0 / 2097152.0);
        p->vel[k] = (double)((r >> (21 * k + 3)) & 0xff) - 128.0;
    }
    p->id = i + 1;
}

/* Particles per file: a block's Fortran record marker is a 32-bit length,
 * so a POS block (12 bytes a particle) must stay under 2 GiB. Larger
 * snapshots are written as FILE.0, FILE.1, ... as Gadget itself does. */
#define PER_FILE 150000000LL

typedef struct file_offset {
    uint64_t first; /* global index of the file's first particle */
} file_offset;

static void generate_in_file(void *user, uint64_t i, int type, gw_particle *p)
{
    generate_particle(NULL, ((const file_offset *)user)->first + i, type, p);
}

/* Writes n particles of type 1 to path, or to path.0, path.1, ... when
 * they do not fit in one file. Returns the number of files, or -1. */
static int generate(const char *path, long long n)
{
    if (n > 4000000000LL) {
        fprintf(stderr, "too many particles: at most 4e9 (npartTotal is 32-bit)\n");
        return -1;
    }
    int nfiles = (int)((n + PER_FILE - 1) / PER_FILE);
    gw_spec spec = {.snapformat = 2, .blocks = GW_VEL | GW_ID, .num_files = nfiles, .time = 1.0, .box_size = 100,
                    .omega0 = 0.3, .omega_lambda = 0.7, .hubble_param = 0.7};
    spec.massarr[1] = 1e-3;
    spec.npart_total[1] = (uint32_t)n;
    double t0 = wall_seconds();
    for (int f = 0; f < nfiles; f++) {
        file_offset off = {(uint64_t)f * PER_FILE};
        long long left = n - (long long)off.first;
        spec.npart[1] = (int32_t)(left < PER_FILE ? left : PER_FILE);
        char name[4096];
        snprintf(name, sizeof name, nfiles > 1 ? "%s.%d" : "%s", path, f);
        if (gw_write(name, &spec, generate_in_file, &off) != 0) {
            fprintf(stderr, "%s: cannot write: %s\n", name, strerror(errno));
            return -1;
        }
    }
    printf("generate:    %.2f s, %d file%s, peak RSS so far %.1f MiB\n", wall_seconds() - t0, nfiles, nfiles > 1 ? "s" : "",
           peak_rss_mib());
    return nfiles;
}

static int plain_read(const char *path, double size)
{
    static char buf[1 << 20];
    int fd = open(path, O_RDONLY);
    if (fd < 0) {
        perror(path);
        return 1;
    }
    double t0 = wall_seconds();
    ssize_t got;
    long long total = 0;
    while ((got = read(fd, buf, sizeof buf)) > 0)
        total += got;
    double dt = wall_seconds() - t0;
    close(fd);
    if (got < 0 || (double)total != size) {
        fprintf(stderr, "%s: read error\n", path);
        return 1;
    }
    printf("plain read:  %.3f s, %.0f MB/s, peak RSS so far %.1f MiB\n", dt, size / dt / 1e6, peak_rss_mib());
    return 0;
}

static int reader_read(const char *path, double size, size_t chunk)
{
    const char *const no_fields[1] = {NULL};
    orr_source_options opt = {.format = "gadget", .chunk_size = chunk, .fields = no_fields, .nfields = 0};
    orr_source *src;
    orr_error err = {0};
    double t0 = wall_seconds();
    if (orr_gadget_source_open(path, &opt, &src, &err) != ORR_OK) {
        fprintf(stderr, "%s\n", err.msg);
        return 1;
    }
    const orr_chunk *c;
    uint64_t n = 0;
    double mass = 0, xsum = 0;
    orr_status st;
    while ((st = orr_source_next(src, &c, &err)) == ORR_OK && c->n > 0) {
        for (size_t i = 0; i < c->n; i++) { /* touch the data, as a renderer would */
            mass += c->mass[i];
            xsum += c->x[i];
        }
        n += c->n;
    }
    double dt = wall_seconds() - t0;
    orr_source_close(src);
    if (st != ORR_OK) {
        fprintf(stderr, "%s\n", err.msg);
        return 1;
    }
    printf("reader:      %.3f s, %.0f MB/s of file, %.3g particles/s, %llu particles, total mass %.6g, "
           "mean x %.4f\n",
           dt, size / dt / 1e6, (double)n / dt, (unsigned long long)n, mass, n ? xsum / (double)n : 0.0);
    printf("peak RSS:    %.1f MiB (whole process)\n", peak_rss_mib());
    return 0;
}

static int usage(void)
{
    fprintf(stderr, "usage: bench_gadget_stream (--generate FILE --particles N | --read FILE) [--chunk N]\n");
    return 2;
}

int main(int argc, char **argv)
{
    const char *gen = NULL, *path = NULL;
    long long particles = 0;
    size_t chunk = 0;
    for (int i = 1; i < argc; i++) {
        if (i + 1 >= argc)
            return usage();
        if (strcmp(argv[i], "--generate") == 0)
            gen = path = argv[++i];
        else if (strcmp(argv[i], "--read") == 0)
            path = argv[++i];
        else if (strcmp(argv[i], "--particles") == 0)
            particles = (long long)strtod(argv[++i], NULL);
        else if (strcmp(argv[i], "--chunk") == 0)
            chunk = (size_t)strtod(argv[++i], NULL);
        else
            return usage();
    }
    if (!path || (gen && particles <= 0))
        return usage();
    int nfiles = gen ? generate(gen, particles) : 1;
    if (nfiles < 0)
        return 1;
    if (nfiles > 1) { /* the timed reads below are of one file */
        printf("wrote %s.0 to %s.%d: read them with orrery render (bench/bench_billion.sh)\n", gen, gen, nfiles - 1);
        return 0;
    }
    struct stat sb;
    if (stat(path, &sb) != 0) {
        perror(path);
        return 1;
    }
    double size = (double)sb.st_size;
    printf("file:        %s, %.0f bytes (%.2f GB)\n", path, size, size / 1e9);
    if (plain_read(path, size) != 0)
        return 1;
    return reader_read(path, size, chunk);
}
