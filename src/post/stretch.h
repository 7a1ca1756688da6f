/* Stretches map linear plane values to display values in [0, 1].
 *   linear: t = v / white
 *   log:    t = log(1 + n v / white) / log(1 + n)      (the paper's log stretch)
 *   asinh:  t = asinh(n v / white) / asinh(n)
 * Everything is clipped to [0, 1]; negative and NaN values map to 0.
 * white is the value shown at full brightness: fixed, or (when 0) taken as a
 * percentile of the image's positive pixels. */
#ifndef ORR_POST_STRETCH_H
#define ORR_POST_STRETCH_H

#include <stddef.h>

#include "core/error.h"
#include "core/names.h"
#include "core/plane.h"

typedef enum {
    ORR_STRETCH_LINEAR,
    ORR_STRETCH_LOG,
    ORR_STRETCH_ASINH,
} orr_stretch_kind;

typedef struct orr_stretch {
    orr_stretch_kind kind;
    double white;            /* > 0: fixed; 0: automatic from white_percentile */
    double white_percentile; /* in (0, 100], of the positive pixels */
    double n;                /* softening of log and asinh, > 0 */
} orr_stretch;

/* Parses "linear", "log" or "asinh"; returns 0 on an unknown name. */
int orr_stretch_from_name(const char *name, orr_stretch_kind *kind);
extern const orr_named orr_stretch_names[];
const char *orr_stretch_name(orr_stretch_kind kind);

/* The white level the stretch would use for this plane (the fixed value, or
 * the percentile; 1 for an image with no positive pixel). */
orr_status orr_stretch_white(const orr_stretch *s, const orr_plane *plane, double *white, orr_error *err);

/* Writes width*height display values in [0, 1] to out. */
orr_status orr_stretch_apply(const orr_stretch *s, const orr_plane *plane, float *out, double *white_used,
                             orr_error *err);

/* The display values of count plane values in, at white level white (from
 * orr_stretch_white), into out: orr_stretch_apply a span at a time. */
void orr_stretch_span(const orr_stretch *s, double white, const float *in, size_t count, float *out);

#endif
