/* ZIP archives as NumPy's np.savez and np.savez_compressed write them
 * (PKWARE's APPNOTE.TXT): the central directory (ZIP64 included: numpy
 * forces ZIP64 headers), and each member read front to back, stored
 * (method 0) or deflated (method 8, through zlib), with seeks in its
 * uncompressed bytes. Members are read with pread, so any number of them
 * can be read side by side from one open file. */
#ifndef ORR_SOURCE_ZIP_ARCHIVE_H
#define ORR_SOURCE_ZIP_ARCHIVE_H

#include <stddef.h>
#include <stdint.h>
#include <zlib.h>

#include "core/error.h"
#include "core/limits.h"

#define ORR_ZIP_NAME_MAX 256
#define ORR_ZIP_MAX_MEMBERS 4096

typedef struct orr_zip_member {
    char name[ORR_ZIP_NAME_MAX];
    int method;             /* 0 stored, 8 deflated */
    uint64_t csize, usize;  /* bytes in the archive, bytes uncompressed */
    uint32_t crc;
    int64_t data_offset;    /* where its (compressed) bytes start */
} orr_zip_member;

/* Whether the first n bytes of a file start a ZIP archive (a local file
 * header, or the end record of an empty archive). */
int orr_zip_probe(const unsigned char *head, size_t n);

/* Reads the central directory of the archive open as fd (path for
 * messages): *members (malloc'ed, the caller frees) and *n. Refuses
 * multi-disk and encrypted archives, methods other than stored and
 * deflate, and members whose bytes lie outside the file. */
orr_status orr_zip_read_directory(int fd, const char *path, orr_zip_member **members, int *n, orr_error *err);

/* A member read front to back: its next uncompressed byte is pos. */
typedef struct orr_zip_reader {
    int fd;
    const orr_zip_member *m;
    char what[ORR_PATH_MAX + ORR_ZIP_NAME_MAX + 16]; /* "path: member 'name'", for messages */
    uint64_t pos;                     /* uncompressed bytes delivered */
    uint64_t cpos;                    /* compressed bytes taken from the file */
    uint32_t crc;                     /* of the bytes delivered, checked at the end of a deflated member */
    int inflating;                    /* zs is initialised */
    z_stream zs;
    unsigned char *in;                /* compressed bytes read, not yet inflated */
} orr_zip_reader;

orr_status orr_zip_reader_open(orr_zip_reader *r, int fd, const char *path, const orr_zip_member *m,
                               orr_error *err);
/* The next n bytes of the member into buf: all of them, or an error
 * (a member that ends early, a damaged stream, a CRC that disagrees). */
orr_status orr_zip_read(orr_zip_reader *r, void *buf, size_t n, orr_error *err);
/* Moves to uncompressed byte to: a deflated member forwards by inflating
 * and dropping, backwards by starting again. */
orr_status orr_zip_seek(orr_zip_reader *r, uint64_t to, orr_error *err);
void orr_zip_reader_close(orr_zip_reader *r);

#endif
