#include "scene/scene_file.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Scene files are a few hundred bytes; the cap only stops a wrong path (a
 * snapshot, a device) from being read into memory. */
#define SCENE_FILE_MAX (16u << 20)

/* Reads all of f into a buffer with room for a final NUL; *len is the bytes read. */
static orr_status read_all(FILE *f, const char *path, const char *what, char **out, size_t *len,
                           orr_error *err)
{
    size_t cap = 4096;
    char *buf = orr_malloc(cap, what, err);
    if (!buf)
        return ORR_ERR_NOMEM;
    orr_status st = ORR_OK;
    *len = 0;
    while (st == ORR_OK) {
        if (*len + 1 == cap) {
            char *bigger = cap >= SCENE_FILE_MAX ? NULL : realloc(buf, 2 * cap);
            if (!bigger) {
                st = cap >= SCENE_FILE_MAX
                         ? orr_fail(err, ORR_ERR_USAGE, "%s: larger than %u bytes; not a %s", path, SCENE_FILE_MAX,
                                    what)
                         : orr_fail(err, ORR_ERR_NOMEM, "%s: out of memory reading the %s", path, what);
                break;
            }
            buf = bigger;
            cap *= 2;
        }
        size_t got = fread(buf + *len, 1, cap - 1 - *len, f);
        *len += got;
        if (got == 0 && ferror(f))
            st = orr_fail(err, ORR_ERR_IO, "%s: cannot read %s: %s", path, what, strerror(errno));
        else if (got == 0)
            break;
    }
    if (st != ORR_OK) {
        free(buf);
        return st;
    }
    buf[*len] = '\0';
    *out = buf;
    return ORR_OK;
}

orr_status scene_read_text(const char *path, const char *what, char **out, orr_error *err)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return orr_fail(err, ORR_ERR_IO, "%s: cannot open %s: %s", path, what, strerror(errno));
    char *text = NULL;
    size_t len = 0;
    orr_status st = read_all(f, path, what, &text, &len, err);
    fclose(f);
    if (st != ORR_OK)
        return st;
    if (strlen(text) != len) {
        free(text);
        return orr_fail(err, ORR_ERR_USAGE, "%s: contains a NUL byte; not a text file", path);
    }
    *out = text;
    return ORR_OK;
}

void scene_path_stem(const char *path, char *out, size_t size)
{
    const char *slash = strrchr(path, '/');
    const char *base = slash ? slash + 1 : path;
    const char *dot = strrchr(base, '.');
    size_t len = (dot && dot != base) ? (size_t)(dot - base) : strlen(base);
    if (len >= size)
        len = size - 1;
    memcpy(out, base, len);
    out[len] = '\0';
}

void scene_path_dir(const char *path, char *out, size_t size)
{
    const char *slash = strrchr(path, '/');
    if (!slash)
        snprintf(out, size, ".");
    else if (slash == path)
        snprintf(out, size, "/");
    else
        snprintf(out, size, "%.*s", (int)(slash - path), path);
}
