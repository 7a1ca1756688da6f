#include "render/frame_names.h"

#include <stdio.h>

orr_frame_naming orr_frame_naming_of(const orr_output_settings *o)
{
    orr_frame_naming f = ORR_FRAME_NAMING_DEFAULT;
    f.start = o->frame_start;
    if (o->frame_digits > 0)
        f.digits = o->frame_digits;
    if (o->frame_separator[0])
        f.separator = o->frame_separator;
    return f;
}

int orr_frame_digits(const orr_frame_naming *f, long nframes)
{
    int digits = f->digits > 0 ? f->digits : 4;
    long long last = f->start + (nframes > 0 ? nframes - 1 : 0), top = 1;
    for (int k = 0; k < digits && top <= last; k++)
        top *= 10;
    /* Widened rather than refused: a name with one digit more still sorts
     * and plays in order, a run stopped at its 10^digits-th frame does not. */
    for (; last >= top && digits < 18; top *= 10)
        digits++;
    return digits;
}

orr_status orr_frame_name_fixed(const orr_frame_naming *f, const char *name, long frame, char *out, size_t size,
                                orr_error *err)
{
    int n = snprintf(out, size, "%s%s%0*lld", name, f->separator ? f->separator : "_", f->digits,
                     f->start + (long long)frame);
    if (n < 0 || (size_t)n >= size)
        return orr_fail(err, ORR_ERR_USAGE, "output name %s with a frame number is too long", name);
    return ORR_OK;
}

orr_status orr_frame_name(const orr_frame_naming *f, const char *name, long frame, long nframes, char *out,
                          size_t size, orr_error *err)
{
    if (nframes <= 1) {
        int n = snprintf(out, size, "%s", name);
        if (n < 0 || (size_t)n >= size)
            return orr_fail(err, ORR_ERR_USAGE, "output name %s is too long", name);
        return ORR_OK;
    }
    orr_frame_naming wide = *f;
    wide.digits = orr_frame_digits(f, nframes);
    return orr_frame_name_fixed(&wide, name, frame, out, size, err);
}
