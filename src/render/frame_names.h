/* Output names of a run's frames: NAME_0007 (output.frame_start,
 * .frame_digits, .frame_separator), NAME for a still. The animation driver
 * (animation.c) and the plan (plan.c) name frames with them. */
#ifndef ORR_RENDER_FRAME_NAMES_H
#define ORR_RENDER_FRAME_NAMES_H

#include <stddef.h>

#include "core/error.h"
#include "encode/output_settings.h"

/* How frame numbers are written into output names: NAME, the separator,
 * then start + frame with at least `digits` digits, zero-padded
 * (output.frame_start, output.frame_digits, output.frame_separator). The
 * default, ORR_FRAME_NAMING_DEFAULT, gives NAME_0000 from 0; the fulldome
 * convention {1, 5, "."} gives NAME.00001 from 1. */
typedef struct orr_frame_naming {
    long long start;
    int digits;
    const char *separator;
} orr_frame_naming;

#define ORR_FRAME_NAMING_DEFAULT ((orr_frame_naming){.start = 0, .digits = 4, .separator = "_"})

/* The naming output.frame_* (o) ask for. */
orr_frame_naming orr_frame_naming_of(const orr_output_settings *o);

/* Where a view writes its files and its frames' markers: output.dir, its
 * output.name (a frame's scene's: with the frame's number) and how frames
 * are named. Compiled by the plan from a scene (orr_plan_output_place,
 * render/plan.h); it points into that scene. */
typedef struct orr_output_place {
    const char *dir;         /* output.dir */
    const char *name;        /* output.name */
    orr_frame_naming naming; /* output.frame_* */
} orr_output_place;

/* Digits of the frame numbers in a run of nframes: f's, more when the last
 * frame's number needs them. */
int orr_frame_digits(const orr_frame_naming *f, long nframes);

/* The output name of frame `frame` (0-based) of a run of `nframes`: NAME_%04ld
 * by default, as f says otherwise; NAME itself for a still. */
orr_status orr_frame_name(const orr_frame_naming *f, const char *name, long frame, long nframes, char *out,
                          size_t size, orr_error *err);

/* The same with exactly f->digits digits (a run whose length is unknown). */
orr_status orr_frame_name_fixed(const orr_frame_naming *f, const char *name, long frame, char *out, size_t size,
                                orr_error *err);

#endif
