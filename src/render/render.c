/* The renderer's entry points: a still's render or compose as a plan made,
 * executed once and destroyed (render/plan.h; plan.c holds the frame). What
 * the scene asks of its particle source the plan compiles
 * (render/source_request.h); scene_source.c opens it. */
#include "render/render.h"

#include "render/plan.h"

orr_status orr_render_views(const orr_scene *const *scenes, int n, orr_render_report *reports,
                            orr_progress_fn progress, void *progress_user, orr_error *err)
{
    return orr_render_frame(scenes, n, NULL, reports, progress, progress_user, err);
}

/* One frame alone: a plan made, executed once and destroyed. A run of
 * frames keeps its plan instead (animation.c, insitu/insitu.c). */
orr_status orr_render_frame(const orr_scene *const *scenes, int n, const orr_frame_input *in,
                            orr_render_report *reports, orr_progress_fn progress, void *progress_user,
                            orr_error *err)
{
    orr_plan *plan;
    orr_status st = orr_plan_create(&plan, scenes, n, ORR_PLAN_RENDER, err);
    if (!st)
        st = orr_plan_execute(plan, in, reports, progress, progress_user, err);
    orr_plan_destroy(plan);
    return st;
}

orr_status orr_compose_views(const orr_scene *const *scenes, int n, orr_render_report *reports, orr_error *err)
{
    orr_plan *plan;
    orr_status st = orr_plan_create(&plan, scenes, n, ORR_PLAN_COMPOSE, err);
    if (!st)
        st = orr_plan_compose(plan, NULL, reports, err);
    orr_plan_destroy(plan);
    return st;
}

orr_status orr_render_scene(const orr_scene *scene, orr_render_report *report, orr_progress_fn progress,
                            void *progress_user, orr_error *err)
{
    return orr_render_views(&scene, 1, report, progress, progress_user, err);
}
