#include "core/fits_scan.h"

#include <fcntl.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#define FITS_BLOCK 2880
#define FITS_CARD 80
#define MAX_HDUS 100000

/* What the scan needs of one header. */
typedef struct header_facts {
    long long bitpix, naxis, naxes[999], pcount, gcount;
    int compressed, ended;
} header_facts;

/* The card's value as an integer (0 when it is not one). */
static long long card_integer(const char *card)
{
    char value[FITS_CARD - 9];
    memcpy(value, card + 10, sizeof value - 1);
    value[sizeof value - 1] = '\0';
    return strtoll(value, NULL, 10);
}

static void read_card(const char *card, header_facts *h)
{
    char key[9];
    memcpy(key, card, 8);
    key[8] = '\0';
    for (int i = 7; i >= 0 && key[i] == ' '; i--)
        key[i] = '\0';
    int has_value = card[8] == '=';
    if (strcmp(key, "END") == 0)
        h->ended = 1;
    else if (!has_value)
        return;
    else if (strcmp(key, "BITPIX") == 0)
        h->bitpix = card_integer(card);
    else if (strcmp(key, "NAXIS") == 0)
        h->naxis = card_integer(card);
    else if (strcmp(key, "PCOUNT") == 0)
        h->pcount = card_integer(card);
    else if (strcmp(key, "GCOUNT") == 0)
        h->gcount = card_integer(card);
    else if (strcmp(key, "ZIMAGE") == 0)
        h->compressed = strspn(card + 10, " ") < FITS_CARD - 10 && card[10 + strspn(card + 10, " ")] == 'T';
    else if (strncmp(key, "NAXIS", 5) == 0) {
        long n = strtol(key + 5, NULL, 10);
        if (n >= 1 && n <= 999)
            h->naxes[n - 1] = card_integer(card);
    }
}

/* Reads one header from f; 0 when the file ends first. */
static int read_header(FILE *f, header_facts *h)
{
    memset(h, 0, sizeof *h);
    h->gcount = 1;
    char block[FITS_BLOCK];
    while (!h->ended) {
        if (fread(block, 1, FITS_BLOCK, f) != FITS_BLOCK)
            return 0;
        for (int c = 0; c < FITS_BLOCK / FITS_CARD && !h->ended; c++)
            read_card(block + c * FITS_CARD, h);
    }
    return 1;
}

/* Bytes of the data after the header, padded to whole blocks; -1 when the
 * header's numbers make no sense (the scan then leaves it to cfitsio). */
static long long data_bytes(const header_facts *h)
{
    long long bytes = h->bitpix < 0 ? -h->bitpix / 8 : h->bitpix / 8;
    if (bytes <= 0 || h->naxis < 0 || h->naxis > 999 || h->pcount < 0 || h->gcount < 0)
        return -1;
    if (h->naxis == 0)
        return 0;
    long long count = 1;
    for (long long i = 0; i < h->naxis; i++) {
        if (h->naxes[i] < 0 || (h->naxes[i] > 0 && count > INT64_MAX / 16 / h->naxes[i]))
            return -1;
        count *= h->naxes[i];
    }
    if (count > INT64_MAX / 16 - h->pcount || (h->gcount > 0 && count + h->pcount > INT64_MAX / 16 / h->gcount))
        return -1;
    long long total = bytes * h->gcount * (count + h->pcount);
    return (total + FITS_BLOCK - 1) / FITS_BLOCK * FITS_BLOCK;
}

orr_status orr_fits_refuse_compressed(const char *path, const char *what, orr_error *err)
{
    /* O_NONBLOCK: a FIFO's open would wait for a writer; cfitsio reads
     * with seeks, and a device such as /dev/zero never ends. */
    int fd = open(path, O_RDONLY | O_NONBLOCK);
    struct stat sb;
    if (fd >= 0 && fstat(fd, &sb) == 0 && !S_ISREG(sb.st_mode)) {
        close(fd);
        return orr_fail(err, ORR_ERR_USAGE, "%s: %s; orrery reads %s from a regular FITS file (FITS files are "
                        "read with seeks)", path, S_ISFIFO(sb.st_mode) ? "a pipe or FIFO" : S_ISCHR(sb.st_mode)
                        ? "a character device" : S_ISDIR(sb.st_mode) ? "a folder" : "not a regular file", what);
    }
    FILE *f = fd >= 0 ? fdopen(fd, "rb") : NULL;
    if (!f) {
        if (fd >= 0)
            close(fd);
        return ORR_OK;
    }
    header_facts *h = malloc(sizeof *h);
    orr_status st = ORR_OK;
    for (int hdu = 1; h && hdu <= MAX_HDUS && read_header(f, h); hdu++) {
        if (h->compressed) {
            st = orr_fail(err, ORR_ERR_FORMAT,
                          "%s: HDU %d is a tile-compressed image; orrery reads %s uncompressed (funpack the file "
                          "first)",
                          path, hdu, what);
            break;
        }
        long long skip = data_bytes(h);
        if (skip < 0 || fseeko(f, (off_t)skip, SEEK_CUR) != 0)
            break;
    }
    free(h);
    fclose(f);
    return st;
}
