/* The dust stage's hook in the render driver (docs/dust.md): the frame's
 * dust, read once and shared by every view (dust/dust.h does the work). */
#include "pass/splat_view.h"

/* The frame's dust (dust.types), read in a pass of its own and shared by
 * every view; each view dims its stars from its own eye. */
orr_status orr_dust_view_prepare(orr_splat_view *const *views, int n, orr_source *src, orr_dust_frame *dust,
                                 orr_error *err)
{
    const orr_splat_settings *set = &views[0]->splat;
    double support = src->info.h_support > 0 ? src->info.h_support : 2.0;
    orr_dust_context ctx = {.scene_path = set->path,
                            .kernel = set->deposit.kernel,
                            .neighbours = set->deposit.neighbours,
                            .h_scale = set->deposit.h_scale * support / 2.0,
                            .colour = set->has_populations,
                            .drawn_types = set->type_mask};
    orr_status st = orr_dust_frame_prepare(dust, &set->dust, &ctx, src, err);
    for (int k = 0; k < n && !st; k++)
        views[k]->dust = dust;
    if (st)
        orr_dust_frame_free(dust);
    return st;
}
