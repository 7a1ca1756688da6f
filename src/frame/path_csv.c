/* Keyframes from a CSV file (orr_path_read_csv; the format is in
 * docs/paths.md). The header names the columns, so their order is free and
 * a file says what it holds. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/numbers.h"
#include "frame/path.h"

enum {
    COL_FRAME, COL_X, COL_Y, COL_Z,
    COL_LOOK_X, COL_LOOK_Y, COL_LOOK_Z,
    COL_DIR_X, COL_DIR_Y, COL_DIR_Z,
    COL_QW, COL_QX, COL_QY, COL_QZ,
    COL_UP_X, COL_UP_Y, COL_UP_Z,
    COL_ROLL,
    NCOLS
};

static const char *const COL_NAMES[NCOLS] = {
    "frame", "x", "y", "z", "look_x", "look_y", "look_z", "dir_x", "dir_y", "dir_z",
    "qw", "qx", "qy", "qz", "up_x", "up_y", "up_z", "roll",
};

#define KNOWN_COLUMNS "frame x y z, look_x look_y look_z | dir_x dir_y dir_z | qw qx qy qz, up_x up_y up_z, roll"
#define LINE_MAX_LEN 4096
#define FIELDS_MAX 32

typedef struct csv_layout {
    int ncols;              /* columns in the header */
    int col_of[NCOLS];      /* header position of each known column, -1 when absent */
    orr_key_aim aim;
    int has_up, has_roll;
} csv_layout;

/* Splits line in place at commas, trimming spaces; returns the count, or
 * FIELDS_MAX + 1 when there are more fields than that. */
static int split_fields(char *line, char **fields)
{
    int n = 0;
    char *p = line;
    for (;;) {
        if (n == FIELDS_MAX)
            return FIELDS_MAX + 1;
        while (*p == ' ' || *p == '\t')
            p++;
        fields[n++] = p;
        char *comma = strchr(p, ',');
        char *end = comma ? comma : p + strlen(p);
        while (end > p && (end[-1] == ' ' || end[-1] == '\t' || end[-1] == '\r' || end[-1] == '\n'))
            end--;
        if (!comma) {
            *end = '\0';
            return n;
        }
        *end = '\0';
        p = comma + 1;
    }
}

/* Whether all, none or some of the columns [first, first + count) are present. */
static int group_count(const csv_layout *l, int first, int count)
{
    int have = 0;
    for (int c = first; c < first + count; c++)
        have += l->col_of[c] >= 0;
    return have;
}

static orr_status check_group(const csv_layout *l, const char *file, int first, int count, orr_error *err)
{
    int have = group_count(l, first, count);
    if (have == 0 || have == count)
        return ORR_OK;
    for (int c = first; c < first + count; c++)
        if (l->col_of[c] < 0)
            return orr_fail(err, ORR_ERR_FORMAT, "%s:1: column '%s' is missing (its group needs all of %s..%s)", file,
                            COL_NAMES[c], COL_NAMES[first], COL_NAMES[first + count - 1]);
    return ORR_OK;
}

static orr_status parse_header(char *line, const char *file, csv_layout *l, orr_error *err)
{
    char *fields[FIELDS_MAX];
    int n = split_fields(line, fields);
    if (n > FIELDS_MAX)
        return orr_fail(err, ORR_ERR_FORMAT, "%s:1: more than %d columns", file, FIELDS_MAX);
    for (int c = 0; c < NCOLS; c++)
        l->col_of[c] = -1;
    l->ncols = n;
    for (int i = 0; i < n; i++) {
        int c = 0;
        while (c < NCOLS && strcmp(fields[i], COL_NAMES[c]) != 0)
            c++;
        if (c == NCOLS)
            return orr_fail(err, ORR_ERR_FORMAT, "%s:1: unknown column '%s' (known: %s)", file, fields[i],
                            KNOWN_COLUMNS);
        if (l->col_of[c] >= 0)
            return orr_fail(err, ORR_ERR_FORMAT, "%s:1: column '%s' appears twice", file, fields[i]);
        l->col_of[c] = i;
    }
    for (int c = COL_FRAME; c <= COL_Z; c++)
        if (l->col_of[c] < 0)
            return orr_fail(err, ORR_ERR_FORMAT, "%s:1: column '%s' is missing (needed: frame, x, y, z)", file,
                            COL_NAMES[c]);
    orr_status st;
    if ((st = check_group(l, file, COL_LOOK_X, 3, err)) || (st = check_group(l, file, COL_DIR_X, 3, err)) ||
        (st = check_group(l, file, COL_QW, 4, err)) || (st = check_group(l, file, COL_UP_X, 3, err)))
        return st;
    const int look = l->col_of[COL_LOOK_X] >= 0, dir = l->col_of[COL_DIR_X] >= 0, quat = l->col_of[COL_QW] >= 0;
    if (look + dir + quat != 1)
        return orr_fail(err, ORR_ERR_FORMAT,
                        "%s:1: give exactly one orientation: look_x look_y look_z, dir_x dir_y dir_z or qw qx qy qz "
                        "(got %d)", file, look + dir + quat);
    l->aim = look ? ORR_AIM_LOOK_AT : dir ? ORR_AIM_DIRECTION : ORR_AIM_QUATERNION;
    l->has_up = l->col_of[COL_UP_X] >= 0;
    l->has_roll = l->col_of[COL_ROLL] >= 0;
    if (quat && (l->has_up || l->has_roll))
        return orr_fail(err, ORR_ERR_FORMAT, "%s:1: up_x/up_y/up_z and roll do not apply to a quaternion", file);
    return ORR_OK;
}

static orr_status parse_value(const char *text, const char *file, int line, const char *column, double *v,
                              orr_error *err)
{
    char *end = NULL;
    errno = 0;
    *v = orr_strtod(text, &end);
    if (text[0] == '\0' || end == text || *end != '\0' || !isfinite(*v))
        return orr_fail(err, ORR_ERR_FORMAT, "%s:%d: column '%s': '%s' is not a finite number", file, line, column,
                        text);
    return ORR_OK;
}

static orr_status parse_row(char *text, const char *file, int line, const csv_layout *l, orr_keyframe_spec *spec,
                            orr_error *err)
{
    char *fields[FIELDS_MAX];
    int n = split_fields(text, fields);
    if (n != l->ncols)
        return orr_fail(err, ORR_ERR_FORMAT, "%s:%d: %s%d values, expected %d (one per column of the header)", file,
                        line, n > FIELDS_MAX ? "more than " : "", n > FIELDS_MAX ? FIELDS_MAX : n, l->ncols);
    double v[NCOLS] = {0};
    for (int c = 0; c < NCOLS; c++) {
        if (l->col_of[c] < 0)
            continue;
        orr_status st = parse_value(fields[l->col_of[c]], file, line, COL_NAMES[c], &v[c], err);
        if (st)
            return st;
    }
    memset(spec, 0, sizeof *spec);
    spec->frame = v[COL_FRAME];
    spec->position = orr_v3(v[COL_X], v[COL_Y], v[COL_Z]);
    spec->aim = l->aim;
    if (l->aim == ORR_AIM_LOOK_AT)
        spec->look = orr_v3(v[COL_LOOK_X], v[COL_LOOK_Y], v[COL_LOOK_Z]);
    else if (l->aim == ORR_AIM_DIRECTION)
        spec->look = orr_v3(v[COL_DIR_X], v[COL_DIR_Y], v[COL_DIR_Z]);
    else
        spec->quaternion = (orr_quat){v[COL_QW], v[COL_QX], v[COL_QY], v[COL_QZ]};
    spec->has_up = l->has_up;
    spec->up = orr_v3(v[COL_UP_X], v[COL_UP_Y], v[COL_UP_Z]);
    spec->roll = v[COL_ROLL];
    return ORR_OK;
}

static int skippable(const char *line)
{
    line += strspn(line, " \t\r\n");
    return *line == '\0' || *line == '#';
}

static orr_status read_rows(FILE *fp, const char *file, orr_keyframe *keys, int max, int *nkeys, orr_error *err)
{
    char text[LINE_MAX_LEN];
    csv_layout layout = {0};
    int have_header = 0, line = 0;
    *nkeys = 0;
    while (fgets(text, sizeof text, fp)) {
        line++;
        if (!strchr(text, '\n') && !feof(fp))
            return orr_fail(err, ORR_ERR_FORMAT, "%s:%d: line longer than %d characters", file, line,
                            LINE_MAX_LEN - 2);
        if (skippable(text))
            continue;
        orr_status st;
        if (!have_header) {
            if ((st = parse_header(text, file, &layout, err)))
                return st;
            have_header = 1;
            continue;
        }
        if (*nkeys == max)
            return orr_fail(err, ORR_ERR_FORMAT, "%s:%d: more than %d keyframes", file, line, max);
        orr_keyframe_spec spec;
        if ((st = parse_row(text, file, line, &layout, &spec, err)))
            return st;
        if (*nkeys > 0 && !(spec.frame > keys[*nkeys - 1].frame))
            return orr_fail(err, ORR_ERR_FORMAT,
                            "%s:%d: frame %g is not after the previous keyframe's frame %g; keyframes must be in "
                            "increasing frame order", file, line, spec.frame, keys[*nkeys - 1].frame);
        if ((st = orr_keyframe_from_spec(&spec, &keys[*nkeys], err))) {
            orr_fail_prefix(err, "%s:%d: ", file, line);
            if (err)
                err->code = ORR_ERR_FORMAT; /* the file's contents are wrong, as for the other rows */
            return ORR_ERR_FORMAT;
        }
        ++*nkeys;
    }
    if (ferror(fp))
        return orr_fail(err, ORR_ERR_IO, "%s: read error after line %d", file, line);
    if (!have_header)
        return orr_fail(err, ORR_ERR_FORMAT, "%s: empty: expected a header line naming the columns (%s)", file,
                        KNOWN_COLUMNS);
    if (*nkeys < 2)
        return orr_fail(err, ORR_ERR_FORMAT, "%s: %d keyframe%s; a path needs at least 2", file, *nkeys,
                        *nkeys == 1 ? "" : "s");
    return ORR_OK;
}

orr_status orr_path_read_csv(const char *file, orr_keyframe *keys, int max, int *nkeys, orr_error *err)
{
    FILE *fp = fopen(file, "r");
    if (!fp)
        return orr_fail(err, ORR_ERR_IO, "%s: cannot open: %s", file, strerror(errno));
    orr_status st = read_rows(fp, file, keys, max, nkeys, err);
    fclose(fp);
    return st;
}
