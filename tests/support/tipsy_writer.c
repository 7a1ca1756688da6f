#include "tipsy_writer.h"

#include <stdint.h>
#include <string.h>

/* Writes the low 32 bits of u (or all 64 with n == 8) in the byte order. */
static int put_bytes(FILE *fp, uint64_t u, int n, int big_endian)
{
    unsigned char b[8];
    for (int i = 0; i < n; i++) {
        int shift = big_endian ? 8 * (n - 1 - i) : 8 * i;
        b[i] = (unsigned char)(u >> shift);
    }
    return fwrite(b, 1, (size_t)n, fp) == (size_t)n ? 0 : -1;
}

static int put_int(FILE *fp, int v, int big_endian)
{
    uint32_t u;
    memcpy(&u, &(int32_t){(int32_t)v}, sizeof u);
    return put_bytes(fp, u, 4, big_endian);
}

tipsy_writer_header tipsy_writer_header_for(double time, int nsph, int ndark, int nstar, int big_endian,
                                            int header_size)
{
    tipsy_writer_header h = {time, nsph + ndark + nstar, 3, nsph, ndark, nstar, big_endian, header_size};
    return h;
}

int tipsy_write_header(FILE *fp, const tipsy_writer_header *h)
{
    uint64_t t;
    memcpy(&t, &h->time, sizeof t);
    int bad = put_bytes(fp, t, 8, h->big_endian);
    const int ints[5] = {h->nbodies, h->ndim, h->nsph, h->ndark, h->nstar};
    for (int i = 0; i < 5; i++)
        bad |= put_int(fp, ints[i], h->big_endian);
    if (h->header_size == 32)
        bad |= put_int(fp, 0, h->big_endian); /* the pad */
    return bad;
}

int tipsy_write_floats(FILE *fp, const float *v, size_t n, int big_endian)
{
    for (size_t i = 0; i < n; i++) {
        uint32_t u;
        memcpy(&u, &v[i], sizeof u);
        if (put_bytes(fp, u, 4, big_endian))
            return -1;
    }
    return 0;
}

int tipsy_write_file(const char *path, const tipsy_writer_header *h, const float *gas, const float *dark,
                     const float *star)
{
    FILE *fp = fopen(path, "wb");
    if (!fp)
        return -1;
    int bad = tipsy_write_header(fp, h);
    if (h->nsph > 0)
        bad |= tipsy_write_floats(fp, gas, (size_t)h->nsph * TIPSY_GAS_FLOATS, h->big_endian);
    if (h->ndark > 0)
        bad |= tipsy_write_floats(fp, dark, (size_t)h->ndark * TIPSY_DARK_FLOATS, h->big_endian);
    if (h->nstar > 0)
        bad |= tipsy_write_floats(fp, star, (size_t)h->nstar * TIPSY_STAR_FLOATS, h->big_endian);
    if (fclose(fp) != 0)
        bad = -1;
    return bad;
}
