#include "render/frame_markers.h"

#include <errno.h>
#include <fcntl.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zlib.h>

#include "core/atomic.h"
#include "core/digest.h"
#include "core/numbers.h"

/* ---- frame markers ----
 *
 * A marker, DIR/.orrery-frames/NAME_0007.done, says what made the frame and
 * what it wrote:
 *
 *   orrery-frame 2
 *   version 0.1.0
 *   settings 1f0c2d33a9e5b871          digest of the scene's settings text
 *   input input.file 1234 1700000000.123456789 5a6b7c8d PATH
 *   inputs input.sequence 12 9e3779b97f4a7c15
 *   output 1048576 0c1d2e3f NAME_0007.fits   size, CRC-32 of the bytes, name
 *   setting image.width=640                  the settings text, to name a change
 *
 * A frame is skipped when the lines before the outputs equal what this run
 * would write and every output is there with its size and checksum. */

#define MARKER_FORMAT 2
#define SMALL_INPUT_BYTES (1 << 20) /* inputs up to this size get a checksum too */


/* Appends a formatted line to an allocated text. */
static orr_status append(char **text, orr_error *err, const char *fmt, ...) __attribute__((format(printf, 3, 4)));
static orr_status append(char **text, orr_error *err, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    int add = orr_vsnprintf(NULL, 0, fmt, ap); /* numbers with '.', whatever the host's locale */
    va_end(ap);
    size_t len = *text ? strlen(*text) : 0;
    char *grown = add < 0 ? NULL : realloc(*text, len + (size_t)add + 1);
    if (!grown)
        return orr_fail(err, ORR_ERR_NOMEM, "out of memory for a frame marker");
    va_start(ap, fmt);
    orr_vsnprintf(grown + len, (size_t)add + 1, fmt, ap);
    va_end(ap);
    *text = grown;
    return ORR_OK;
}

#define CRC_PIECE ((size_t)8 << 20) /* files are summed in pieces of this many bytes, on every thread */

/* CRC-32 of len bytes of the open file from offset start; *ok = 0 when
 * they cannot all be read. */
static unsigned long piece_crc(int fd, off_t start, size_t len, int *ok)
{
    static _Thread_local unsigned char buf[1 << 16];
    unsigned long crc = crc32(0L, Z_NULL, 0);
    while (len > 0) {
        ssize_t n = pread(fd, buf, len < sizeof buf ? len : sizeof buf, start);
        if (n < 0 && errno == EINTR)
            continue;
        if (n <= 0) {
            *ok = 0;
            return 0;
        }
        crc = crc32(crc, buf, (uInt)n);
        start += n;
        len -= (size_t)n;
    }
    return crc;
}

/* The length of piece k of size bytes cut into pieces of `piece` bytes. */
static size_t piece_len(size_t size, size_t piece, size_t k)
{
    size_t start = k * piece;
    return size - start < piece ? size - start : piece;
}

/* CRC-32 of the file's bytes; 0 with *ok = 0 when it cannot be read. A
 * frame's outputs are read back for its marker, and an 8192^2 frame's FITS
 * planes are 805 MB: its pieces are summed on every thread and their CRCs
 * joined (zlib's crc32_combine), which gives the whole file's CRC. */
static unsigned long file_crc(const char *path, int *ok)
{
    /* O_NONBLOCK: should a FIFO come here, its open does not wait for a
     * writer (reads of a regular file never block, the flag or not). */
    int fd = open(path, O_RDONLY | O_NONBLOCK);
    struct stat sb;
    *ok = fd >= 0 && fstat(fd, &sb) == 0 && S_ISREG(sb.st_mode);
    size_t size = *ok ? (size_t)sb.st_size : 0, npieces = (size + CRC_PIECE - 1) / CRC_PIECE;
    unsigned long *crcs = *ok && npieces > 1 ? malloc(npieces * sizeof *crcs) : NULL;
    if (!crcs) /* small, or no memory for the pieces' sums: one piece */
        npieces = 1;
    size_t piece = crcs ? CRC_PIECE : size;
    unsigned long crc = 0;
    int all_read = *ok;
#pragma omp parallel for schedule(dynamic) reduction(&& : all_read) if (crcs)
    for (size_t k = 0; k < npieces; k++) {
        unsigned long c = piece_crc(fd, (off_t)(k * piece), piece_len(size, piece, k), &all_read);
        if (crcs)
            crcs[k] = c;
        else
            crc = c;
    }
    for (size_t k = 0; crcs && k < npieces; k++)
        crc = k == 0 ? crcs[0] : crc32_combine(crc, crcs[k], (z_off_t)piece_len(size, piece, k));
    free(crcs);
    if (fd >= 0)
        close(fd);
    *ok = *ok && all_read;
    return *ok ? crc : 0;
}

/* "input LABEL SIZE MTIME CRC PATH": an input file's identity. Its size and
 * modification time always, its checksum when it is a small regular file
 * ("-" otherwise: a FIFO or device is read once, by the reader). */
static orr_status add_input(char **head, const char *label, const char *path, orr_error *err)
{
    struct stat st;
    if (stat(path, &st) != 0)
        return append(head, err, "input %s missing - - %s\n", label, path);
    char crc[16] = "-";
    int ok = 0;
    if (S_ISREG(st.st_mode) && st.st_size <= SMALL_INPUT_BYTES) {
        unsigned long c = file_crc(path, &ok);
        if (ok)
            snprintf(crc, sizeof crc, "%08lx", c);
    }
    return append(head, err, "input %s %lld %lld.%09ld %s %s\n", label, (long long)st.st_size,
                  (long long)st.st_mtim.tv_sec, (long)st.st_mtim.tv_nsec, crc, path);
}

/* "inputs LABEL COUNT DIGEST": many files (a sequence's snapshots) as one
 * digest of their paths, sizes and modification times. */
static orr_status add_input_set(char **head, const char *label, const orr_sequence *seq, orr_error *err)
{
    uint64_t h = ORR_DIGEST_START;
    int n = orr_sequence_count(seq);
    for (int k = 0; k < n; k++) {
        const char *path = orr_sequence_path(seq, k);
        struct stat st;
        long long stamp[3] = {-1, -1, -1};
        if (stat(path, &st) == 0) {
            stamp[0] = (long long)st.st_size;
            stamp[1] = (long long)st.st_mtim.tv_sec;
            stamp[2] = (long long)st.st_mtim.tv_nsec;
        }
        h = orr_digest(orr_digest_text(h, path), stamp, sizeof stamp);
    }
    return append(head, err, "inputs %s %d %016llx\n", label, n, (unsigned long long)h);
}

orr_status orr_view_identity_make(const orr_view_making *m, const orr_sequence *seq, orr_view_identity *id,
                                  orr_error *err)
{
    id->head = NULL;
    id->settings = m->settings;
    orr_status st = append(&id->head, err, "version %s\nsettings %016llx\n", ORRERY_VERSION,
                           (unsigned long long)m->settings_digest);
    if (!st && m->input_file && !seq)
        st = add_input(&id->head, "input.file", m->input_file, err);
    if (!st && seq)
        st = add_input_set(&id->head, "input.sequence", seq, err);
    if (!st && m->psf_file)
        st = add_input(&id->head, "psf.file", m->psf_file, err);
    if (!st && m->camera_path_file)
        st = add_input(&id->head, "camera.path.file", m->camera_path_file, err);
    return st;
}

orr_status orr_marker_path(const orr_output_place *at, char *path, orr_error *err)
{
    int n = snprintf(path, ORR_PATH_MAX, "%s/" MARKER_DIR "/%s.done", at->dir, at->name);
    if (n < 0 || n >= ORR_PATH_MAX)
        return orr_fail(err, ORR_ERR_USAGE, "frame marker path for %s/%s is too long", at->dir, at->name);
    return ORR_OK;
}

/* The whole marker as text, or NULL when there is none (or it is huge:
 * not ours). */
char *orr_marker_read(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return NULL;
    size_t cap = 1 << 20;
    char *text = malloc(cap + 1);
    size_t n = text ? fread(text, 1, cap, f) : 0;
    int whole = text && n < cap && !ferror(f);
    fclose(f);
    if (!whole) {
        free(text);
        return NULL;
    }
    text[n] = '\0';
    return text;
}

/* The line of text that starts with prefix (at a line start), or NULL;
 * *len is its length without the newline. */
const char *orr_marker_find_line(const char *text, const char *prefix, size_t *len)
{
    size_t plen = strlen(prefix);
    for (const char *p = text; p && *p;) {
        const char *end = strchr(p, '\n');
        size_t n = end ? (size_t)(end - p) : strlen(p);
        if (n >= plen && strncmp(p, prefix, plen) == 0) {
            *len = n;
            return p;
        }
        p = end ? end + 1 : NULL;
    }
    return NULL;
}

/* The key of settings line p ("key=value"), as prefix + key + "=". */
static void key_prefix(const char *p, size_t n, const char *prefix, char *out, size_t size)
{
    const char *eq = memchr(p, '=', n);
    size_t klen = eq ? (size_t)(eq - p) : n;
    snprintf(out, size, "%s%.*s=", prefix, (int)(klen < 280 ? klen : 280), p);
}

/* Says which setting differs between the marker's "setting " lines (the
 * earlier frame's) and the text now: "KEY changed from A to B", "KEY=B
 * added" or "KEY=A removed", for the first such key. */
static void name_setting_change(const char *marker, const char *now, char *why, size_t size)
{
    for (const char *p = now; *p;) {
        const char *end = strchr(p, '\n');
        size_t n = end ? (size_t)(end - p) : strlen(p), olen;
        char key[300], line[600];
        key_prefix(p, n, "setting ", key, sizeof key);
        snprintf(line, sizeof line, "setting %.*s\n", (int)(n < 580 ? n : 580), p);
        const char *old = orr_marker_find_line(marker, key, &olen);
        size_t klen = strlen(key) - strlen("setting ");
        if (!old) {
            snprintf(why, size, "%.*s added", (int)(n < 200 ? n : 200), p);
            return;
        }
        if (!strstr(marker, line)) {
            size_t vlen = olen - strlen(key);
            snprintf(why, size, "%.*s changed from %.*s to %.*s", (int)(klen - 1), p, (int)(vlen < 200 ? vlen : 200),
                     old + strlen(key), (int)(n - klen < 200 ? n - klen : 200), p + klen);
            return;
        }
        p = end ? end + 1 : p + n;
    }
    for (const char *p = marker; *p;) {
        const char *end = strchr(p, '\n');
        size_t n = end ? (size_t)(end - p) : strlen(p), nlen;
        char key[300];
        if (strncmp(p, "setting ", 8) == 0) {
            key_prefix(p + 8, n - 8, "", key, sizeof key);
            if (!orr_marker_find_line(now, key, &nlen)) {
                snprintf(why, size, "%.*s removed", (int)(n - 8 < 200 ? n - 8 : 200), p + 8);
                return;
            }
        }
        p = end ? end + 1 : p + n;
    }
    snprintf(why, size, "the settings changed");
}

/* Why the marker's head differs from this run's: the first line that does. */
static void name_head_change(const char *marker, const orr_view_identity *id, char *why, size_t size)
{
    for (const char *p = id->head; *p;) {
        const char *end = strchr(p, '\n');
        size_t n = (size_t)(end - p);
        char line[ORR_PATH_MAX + 256];
        snprintf(line, sizeof line, "%.*s\n", (int)(n < sizeof line - 2 ? n : sizeof line - 2), p);
        if (!strstr(marker, line)) {
            char what[64] = "";
            sscanf(p, "%63s", what);
            if (strcmp(what, "settings") == 0)
                name_setting_change(marker, id->settings, why, size);
            else if (strcmp(what, "version") == 0)
                snprintf(why, size, "made by another version of orrery (this is %s)", ORRERY_VERSION);
            else
                snprintf(why, size, "an input changed since: %.*s", (int)(n < 300 ? n : 300), p);
            return;
        }
        p = end + 1;
    }
    snprintf(why, size, "an input is gone");
}

/* Whether every output the marker lists is in dir as written; else why not. */
static int outputs_hold(const char *marker, const char *dir, char *why, size_t size)
{
    int n = 0;
    for (const char *p = marker; *p;) {
        const char *end = strchr(p, '\n');
        long long bytes;
        unsigned long crc;
        char name[256], path[ORR_PATH_MAX];
        if (sscanf(p, "output %lld %lx %255[^\n]", &bytes, &crc, name) == 3) {
            n++;
            struct stat st;
            int ok;
            if (snprintf(path, sizeof path, "%s/%s", dir, name) >= (int)sizeof path || stat(path, &st) != 0) {
                snprintf(why, size, "%s is missing", name);
                return 0;
            }
            if ((long long)st.st_size != bytes) {
                snprintf(why, size, "%s is %lld bytes, %lld when written", name, (long long)st.st_size, bytes);
                return 0;
            }
            if (file_crc(path, &ok) != crc || !ok) {
                snprintf(why, size, "%s changed since it was written (its checksum differs)", name);
                return 0;
            }
        }
        p = end ? end + 1 : p + strlen(p);
    }
    if (n == 0)
        snprintf(why, size, "its marker lists no output");
    return n > 0;
}

/* Whether the view's frame is complete and made as this run would make it.
 * why is "" when there is no marker (never rendered), else the reason. */
int orr_marker_frame_complete(const orr_output_place *at, const orr_view_identity *id, char *why, size_t size)
{
    char path[ORR_PATH_MAX];
    orr_error ignored;
    why[0] = '\0';
    char *marker = orr_marker_path(at, path, &ignored) ? NULL : orr_marker_read(path);
    if (!marker)
        return 0;
    char magic[32];
    snprintf(magic, sizeof magic, MARKER_MAGIC " %d\n", MARKER_FORMAT);
    int ok = 0;
    if (strncmp(marker, magic, strlen(magic)) != 0)
        snprintf(why, size, "its marker is from an older orrery");
    else if (!strstr(marker, id->head))
        name_head_change(marker, id, why, size);
    else
        ok = outputs_hold(marker, at->dir, why, size);
    free(marker);
    return ok;
}

/* The marker's output lines for this frame's files. */
static orr_status add_outputs(char **text, const orr_render_report *rep, orr_error *err)
{
    orr_status st = ORR_OK;
    for (int i = 0; i < rep->noutputs && !st; i++) {
        const char *path = rep->outputs[i];
        const char *slash = strrchr(path, '/');
        struct stat sb;
        int ok;
        unsigned long crc = file_crc(path, &ok);
        if (!ok || stat(path, &sb) != 0)
            return orr_fail(err, ORR_ERR_IO, "%s: cannot read it back for the frame marker: %s", path,
                            strerror(errno));
        st = append(text, err, "output %lld %08lx %s\n", (long long)sb.st_size, crc, slash ? slash + 1 : path);
    }
    return st;
}

/* Each settings line as "setting KEY=VALUE". */
static orr_status add_settings(char **text, const char *settings, orr_error *err)
{
    orr_status st = ORR_OK;
    for (const char *p = settings; *p && !st;) {
        const char *end = strchr(p, '\n');
        int n = end ? (int)(end - p) : (int)strlen(p);
        st = append(text, err, "setting %.*s\n", n, p);
        p += n + (end != NULL);
    }
    return st;
}

/* Whether marker line p (of n characters) lists an output the report has. */
static int lists_output_of(const char *p, int n, const orr_render_report *rep)
{
    if (strncmp(p, "output ", 7) != 0)
        return 0;
    for (int i = 0; i < rep->noutputs; i++) {
        const char *slash = strrchr(rep->outputs[i], '/');
        const char *name = slash ? slash + 1 : rep->outputs[i];
        int len = (int)strlen(name);
        if (n > len && p[n - len - 1] == ' ' && strncmp(p + n - len, name, (size_t)len) == 0)
            return 1;
    }
    return 0;
}

/* A compose keeps the render's marker and replaces the lines of the
 * pictures it rewrote. */
static orr_status compose_marker_text(const char *old, const orr_render_report *rep, char **text, orr_error *err)
{
    orr_status st = ORR_OK;
    for (const char *p = old; *p && !st;) {
        const char *end = strchr(p, '\n');
        int n = end ? (int)(end - p) : (int)strlen(p);
        if (!lists_output_of(p, n, rep))
            st = append(text, err, "%.*s\n", n, p);
        p += n + (end != NULL);
    }
    return st ? st : add_outputs(text, rep, err);
}

/* The marker's text: a render's whole, or a compose's update of the
 * render's (NULL when the frame has no marker: nothing to update). */
static orr_status marker_text(const orr_output_place *at, const orr_view_identity *id, const orr_render_report *rep,
                              int compose, char **text, orr_error *err)
{
    *text = NULL;
    char path[ORR_PATH_MAX];
    orr_status st = orr_marker_path(at, path, err);
    if (!st && compose) {
        char *old = orr_marker_read(path);
        st = old ? compose_marker_text(old, rep, text, err) : ORR_OK;
        free(old);
        return st;
    }
    if (!st)
        st = append(text, err, MARKER_MAGIC " %d\n%s", MARKER_FORMAT, id->head);
    if (!st)
        st = add_outputs(text, rep, err);
    if (!st) /* the picture's white level, automatic or fixed: what orr_animation_smooth_whites averages */
        st = append(text, err, "white %.17g\n", rep->white);
    return st ? st : add_settings(text, id->settings, err);
}

static orr_status marker_folder(const orr_output_place *at, orr_error *err)
{
    char dir[ORR_PATH_MAX];
    if (snprintf(dir, sizeof dir, "%s/" MARKER_DIR, at->dir) >= (int)sizeof dir)
        return orr_fail(err, ORR_ERR_USAGE, "frame marker folder in %s: path too long", at->dir);
    if (mkdir(dir, 0777) != 0 && errno != EEXIST)
        return orr_fail(err, ORR_ERR_IO, "%s: cannot create the frame marker folder: %s", dir, strerror(errno));
    return ORR_OK;
}

/* Records the view's outputs of this frame. */
orr_status orr_marker_write(const orr_output_place *at, const orr_view_identity *id, const orr_render_report *rep,
                            int compose, orr_error *err)
{
    char path[ORR_PATH_MAX], *text = NULL;
    orr_status st = marker_folder(at, err);
    if (!st)
        st = orr_marker_path(at, path, err);
    if (!st)
        st = marker_text(at, id, rep, compose, &text, err);
    orr_atomic_file af;
    if (!st && !text)
        return ORR_OK;
    if (!st)
        st = orr_atomic_begin(&af, path, err);
    if (st) {
        free(text);
        return st;
    }
    FILE *f = fopen(af.temp_path, "w");
    int ok = f != NULL && fputs(text, f) >= 0;
    if (f && fclose(f) != 0)
        ok = 0;
    free(text);
    if (!ok) {
        orr_atomic_abort(&af);
        return orr_fail(err, ORR_ERR_IO, "%s: cannot write the frame marker", path);
    }
    return orr_atomic_commit(&af, err);
}

/* A frame about to be rendered is not complete until its new marker is
 * written, whatever an old marker said: should the run stop part-way, the
 * next one must not take the old files for this frame's. */
void orr_marker_remove(const orr_output_place *at)
{
    char path[ORR_PATH_MAX];
    orr_error ignored;
    if (!orr_marker_path(at, path, &ignored))
        unlink(path);
}

/* ---- one run's frames together ---- */

/* The marker's head: the lines before its first output line. */
static size_t head_length(const char *marker)
{
    const char *out = strstr(marker, "\noutput ");
    return out ? (size_t)(out - marker) + 1 : strlen(marker);
}

/* The marker's settings lines without their "setting " prefix, allocated. */
static char *marker_settings(const char *marker)
{
    char *text = NULL;
    orr_error ignored;
    for (const char *p = marker; p && *p;) {
        const char *end = strchr(p, '\n');
        int n = end ? (int)(end - p) : (int)strlen(p);
        if (strncmp(p, "setting ", 8) == 0 && append(&text, &ignored, "%.*s\n", n - 8, p + 8))
            break;
        p = end ? end + 1 : NULL;
    }
    return text;
}

/* Fails when frame k's marker was made otherwise than frame `first_k`'s:
 * names the first difference, as "KEY=VALUE (frame first_k) was OTHER". */
static orr_status same_making(const char *first, long first_k, const char *marker, const char *path, long k,
                              orr_error *err)
{
    size_t len = head_length(first);
    if (len == head_length(marker) && strncmp(first, marker, len) == 0)
        return ORR_OK;
    char why[512] = "its marker differs";
    size_t klen = head_length(marker);
    orr_view_identity id = {malloc(klen + 1), marker_settings(marker)}; /* frame k's, against the first's */
    if (id.head && id.settings) {
        memcpy(id.head, marker, klen);
        id.head[klen] = '\0';
        name_head_change(first, &id, why, sizeof why);
    }
    free(id.head);
    free((char *)id.settings);
    return orr_fail(err, ORR_ERR_USAGE,
                    "%s: frame %ld was made otherwise than frame %ld (from frame %ld to frame %ld: %s): the folder "
                    "holds frames of two runs; render the run again",
                    path, k, first_k, first_k, k, why);
}

orr_status orr_frames_agree(const char *dir, const char *name, const orr_frame_naming *f, long count,
                            orr_error *err)
{
    char *first = NULL;
    long first_k = -1;
    orr_status st = ORR_OK;
    for (long k = 0; k < count && !st; k++) {
        char path[ORR_PATH_MAX], frame_name[ORR_NAME_MAX];
        st = orr_frame_name_fixed(f, name, k, frame_name, sizeof frame_name, err);
        if (!st && snprintf(path, sizeof path, "%s/" MARKER_DIR "/%s.done", dir, frame_name) >= (int)sizeof path)
            st = orr_fail(err, ORR_ERR_USAGE, "frame marker path for %s/%s is too long", dir, name);
        char *marker = st ? NULL : orr_marker_read(path);
        if (!marker)
            continue; /* not rendered by this orrery, or by hand: nothing to compare */
        if (!first) {
            first = marker;
            first_k = k;
            continue;
        }
        st = same_making(first, first_k, marker, path, k, err);
        free(marker);
    }
    free(first);
    return st;
}
