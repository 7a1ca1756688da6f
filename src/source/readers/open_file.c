/* Opening a particle file: the reader its format names, or the one whose
 * probe (formats.c) recognises the file's first bytes; standard input, FIFOs
 * and devices read once from the front, which only the text reader can; and
 * the helpers the readers that seek open their files with. Declared in
 * source.h, the interface the rest of orrery opens files through. */
#include "source/source.h"

#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "source/readers/formats.h"
#include "source/readers/text_reader.h"

const char *orr_source_format_names(void)
{
    static char names[256];
    if (!names[0])
        for (int i = 0; i < orr_nformats; i++) {
            if (i)
                strncat(names, " ", sizeof names - strlen(names) - 1);
            strncat(names, orr_formats[i].name, sizeof names - strlen(names) - 1);
        }
    return names;
}

orr_status orr_source_new_file(const char *format, const char *path, const orr_source_ops *ops, size_t state_size,
                               orr_source **out, FILE **fp, orr_error *err)
{
    *out = NULL;
    *fp = NULL;
    orr_status s = orr_source_refuse_stream(path, format, err);
    if (s)
        return s;
    orr_source *src = orr_source_new(format, path, ops, state_size, err);
    if (!src)
        return ORR_ERR_NOMEM;
    if (!(*fp = fopen(path, "rb"))) {
        s = orr_fail(err, ORR_ERR_IO, "%s: cannot open: %s", path, strerror(errno));
        orr_source_close(src);
        return s;
    }
    *out = src;
    return ORR_OK;
}

int orr_source_format_known(const char *name)
{
    for (int i = 0; i < orr_nformats; i++)
        if (strcmp(name, orr_formats[i].name) == 0)
            return 1;
    return 0;
}

/* A multi-file snapshot may be named by its base ("snap_010") when only its
 * parts exist ("snap_010.0", "snap_010.0.hdf5"): the probes then look at the
 * first part. Finds that file with stat(), which, unlike opening, never
 * waits for a FIFO's writer; returns 0 with its name in part, or -1. */
static int find_first_part(const char *path, char *part, size_t size, struct stat *sb)
{
    static const char *const suffixes[] = {"", ".0", ".0.hdf5"};
    for (size_t k = 0; k < sizeof suffixes / sizeof suffixes[0]; k++) {
        if (snprintf(part, size, "%s%s", path, suffixes[k]) >= (int)size)
            break;
        if (stat(part, sb) == 0)
            return 0;
        if (errno != ENOENT)
            return -1;
    }
    errno = ENOENT;
    return -1;
}

/* Reads up to size bytes from the start of path for the probes; returns the
 * count, or -1 with err set when the file cannot be read. */
static long read_head(const char *path, unsigned char *buf, size_t size, orr_error *err)
{
    char part[4096];
    struct stat sb;
    FILE *fp = find_first_part(path, part, sizeof part, &sb) == 0 ? fopen(part, "rb") : NULL;
    if (!fp) {
        orr_fail(err, ORR_ERR_IO, "%s: cannot open: %s", path, strerror(errno));
        return -1;
    }
    size_t n = fread(buf, 1, size, fp);
    int bad = ferror(fp);
    int saved = errno;
    fclose(fp);
    if (bad) {
        orr_fail(err, ORR_ERR_IO, "%s: read error: %s", path, strerror(saved));
        return -1;
    }
    return (long)n;
}

/* ---- streams: standard input, FIFOs, character devices ---- */

/* What a file that is neither regular nor a folder is, for messages. */
static const char *stream_kind(const struct stat *sb)
{
    if (!sb)
        return "standard input";
    if (S_ISFIFO(sb->st_mode))
        return "a pipe or FIFO";
    if (S_ISCHR(sb->st_mode))
        return "a character device";
    if (S_ISSOCK(sb->st_mode))
        return "a socket";
    return "not a regular file";
}

/* Binary formats seek between blocks and read some twice, which a stream
 * cannot do. */
static orr_status refuse_stream(const char *name, const char *kind, const char *format, int detected,
                                orr_error *err)
{
    return orr_fail(err, ORR_ERR_USAGE,
                    "%s: %s%s%s%s files are read with seeks, so the input must be a regular file, but this is %s: "
                    "save it to a file and name that",
                    name, detected ? "holds a " : "", detected ? format : "", detected ? " file, and " : "", format,
                    kind);
}

orr_status orr_source_refuse_stream(const char *path, const char *format, orr_error *err)
{
    struct stat sb;
    if (stat(path, &sb) != 0 || S_ISREG(sb.st_mode) || S_ISDIR(sb.st_mode))
        return ORR_OK;
    return refuse_stream(path, stream_kind(&sb), format, 0, err);
}

/* Detects the format of a stream (sb: what it is; NULL for standard input)
 * from its first bytes, kept for the text reader (the only one that reads
 * front to back), since a stream cannot be read again. Closes fp when it
 * owns it. */
static orr_status open_stream(const char *name, FILE *fp, int owns_fp, const struct stat *sb,
                              const orr_format *named, const orr_source_options *opt, orr_source **out,
                              orr_error *err)
{
    const char *kind = stream_kind(sb);
    unsigned char head[ORR_PROBE_BYTES];
    size_t n = 0;
    orr_status s = ORR_OK;
    if (named && strcmp(named->name, "text") != 0)
        s = refuse_stream(name, kind, named->name, 0, err);
    else
        n = fread(head, 1, sizeof head, fp);
    if (!s && ferror(fp))
        s = orr_fail(err, ORR_ERR_IO, "%s: read error: %s", name, strerror(errno));
    else if (!s && n == 0)
        s = orr_fail(err, ORR_ERR_FORMAT, "%s: no data (%s)%s", name, kind,
                     sb && S_ISFIFO(sb->st_mode)
                         ? ": no program had it open for writing when orrery opened it, or the writer sent "
                           "nothing (orrery does not wait for a writer: start it first)"
                         : "");
    for (int i = 0; !s && !named && i < orr_nformats; i++)
        if (orr_formats[i].probe(head, n)) {
            named = &orr_formats[i];
            if (strcmp(named->name, "text") != 0)
                s = refuse_stream(name, kind, named->name, 1, err);
        }
    if (!s && !named)
        s = orr_fail(err, ORR_ERR_FORMAT, "%s: not a particle file orrery recognises (formats: %s)", name,
                     orr_source_format_names());
    if (s) {
        if (owns_fp)
            fclose(fp);
        return s;
    }
    return orr_text_source_open_stream(name, fp, owns_fp, head, n, opt, out, err);
}

/* Opens a FIFO or device for the text reader. O_NONBLOCK: a FIFO's open
 * waits for a writer, forever when there is none; without the wait, a FIFO
 * with no writer reads as empty, and reads block as usual once the flag is
 * cleared. Binary formats are refused before opening. */
static orr_status open_path_stream(const char *path, const struct stat *sb, const orr_format *named,
                                   const orr_source_options *opt, orr_source **out, orr_error *err)
{
    if (named && strcmp(named->name, "text") != 0)
        return refuse_stream(path, stream_kind(sb), named->name, 0, err);
    int fd = open(path, O_RDONLY | O_NONBLOCK);
    if (fd < 0)
        return orr_fail(err, ORR_ERR_IO, "%s: cannot open: %s", path, strerror(errno));
    int flags = fcntl(fd, F_GETFL);
    FILE *fp = flags >= 0 && fcntl(fd, F_SETFL, flags & ~O_NONBLOCK) == 0 ? fdopen(fd, "rb") : NULL;
    if (!fp) {
        int saved = errno;
        close(fd);
        return orr_fail(err, ORR_ERR_IO, "%s: cannot open: %s", path, strerror(saved));
    }
    return open_stream(path, fp, 1, sb, named, opt, out, err);
}

orr_status orr_source_open_file(const char *path, const orr_source_options *opt, orr_source **out,
                                orr_error *err)
{
    *out = NULL;
    const char *format = opt && opt->format ? opt->format : "auto";
    const orr_format *named = NULL;
    for (int i = 0; i < orr_nformats; i++)
        if (strcmp(format, orr_formats[i].name) == 0)
            named = &orr_formats[i];
    if (!named && strcmp(format, "auto") != 0)
        return orr_fail(err, ORR_ERR_USAGE, "%s: unknown input format '%s' (known: auto %s)", path, format,
                        orr_source_format_names());
    if (strcmp(path, "-") == 0)
        return open_stream("standard input", stdin, 0, NULL, named, opt, out, err);
    char part[4096];
    struct stat sb;
    if (find_first_part(path, part, sizeof part, &sb) == 0 && !S_ISREG(sb.st_mode) && !S_ISDIR(sb.st_mode))
        return open_path_stream(part, &sb, named, opt, out, err);
    if (named)
        return named->open(path, opt, out, err);
    unsigned char head[ORR_PROBE_BYTES];
    long n = read_head(path, head, sizeof head, err);
    if (n < 0)
        return err ? err->code : ORR_ERR_IO;
    for (int i = 0; i < orr_nformats; i++)
        if (orr_formats[i].probe(head, (size_t)n))
            return orr_formats[i].open(path, opt, out, err);
    return orr_fail(err, ORR_ERR_FORMAT,
                    "%s: not a particle file orrery recognises (formats: %s); name one with --format "
                    "or input.format if it is one of them",
                    path, orr_source_format_names());
}
