/* What a view's files are and how its picture is graded, as the writers
 * read them (view_outputs.c, view_cards.c, compose.c, stereo_view.c): the
 * view's own copy, made by the plan (plan_view.c; with plan.c the only
 * reader of the scene), which keeps no pointer into the scene. The frame's part (output.name with
 * the frame's number and an eye's name; the grading, which a compose's
 * re-grade and a stereo pair's shared white level change) is made again
 * from the planned part when each frame begins. */
#ifndef ORR_RENDER_VIEW_FILES_H
#define ORR_RENDER_VIEW_FILES_H

#include "core/limits.h"
#include "encode/output_settings.h"
#include "post/colour.h"
#include "post/picture.h"
#include "scene/compose_settings.h"

typedef struct view_files {
    /* The plan's. */
    char *path;                      /* the scene file, for messages: the view's own copy (core/owned.h) */
    char weight[ORR_FIELD_NAME_MAX]; /* input.weight: what a weight plane's picture shows */
    orr_stereo_mode stereo_mode;     /* stereo.mode: a pair's picture */
    int eye;                         /* stereo.eye: 0, or which eye the view is */
    int extinction_plane;            /* dust.extinction_plane */
    int stars_list;                  /* stars.list: NAME.stars.fits */
    orr_compose_settings compose;    /* compose.layers: a copy with its own strings (freed with the plan) */
    char scene_yaml[ORR_SETTINGS_MAX]; /* the scene as YAML: every FITS file's SCENE extension */
    char planned_name[ORR_NAME_MAX]; /* output.name as given: each frame's name is made from it */
    orr_picture_settings planned_picture; /* output.stretch, ... as given: each frame starts from them */
    orr_colour_settings planned_colour;   /* colour.* as given */
    /* The frame's. */
    orr_output_settings output;      /* output.*, a copy with its own strings: output.name is the frame's
                                      * (planned_name with the frame's number, an eye's name) */
    orr_picture_settings picture;    /* output.stretch, .white, ...; stereo.anaglyph */
    orr_colour_settings colour;      /* colour.*: the synthesis, the tint, the populations */
    int regrade_final;               /* a compose re-grades NAME.fits (orr_scene.regrade_final) */
} view_files;

#endif
