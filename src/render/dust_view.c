/* The dust stage's hook in the render driver (docs/dust.md): the frame's
 * dust, read once and shared by every view (dust/dust.h does the work). */
#include "render/view_state.h"

/* The frame's dust (dust.types), read in a pass of its own and shared by
 * every view; each view dims its stars from its own eye. */
orr_status orr_dust_view_prepare(view_state *views, int n, orr_source *src, const orr_parallel *par,
                                 orr_dust_frame *dust, orr_error *err)
{
    const orr_scene *s = views[0].scene;
    /* Every process dims its share of the stars by all of the dust: on MPI
     * ranks each reads the whole input for it (a simulation's in-situ share
     * cannot be). */
    orr_source *whole = NULL;
    if (par && s->input.insitu)
        return orr_fail(err, ORR_ERR_USAGE, "%s: dust.types: in situ on %d MPI ranks each process holds only its "
                        "share of the dust (docs/dust.md#limitations)", s->path, par->nranks);
    if (par) {
        const char *fields[ORR_RENDER_MAX_FIELDS];
        int nfields = orr_render_fields(s, fields);
        orr_status st = orr_scene_open_source(s, fields, nfields, &whole, err);
        if (st)
            return st;
        src = whole;
    }
    double support = src->info.h_support > 0 ? src->info.h_support : 2.0;
    orr_dust_context ctx = {s->path, s->deposit.kernel, s->deposit.neighbours, s->deposit.h_scale * support / 2.0, s->colour.has_populations, s->input.type_mask};
    orr_status st = orr_dust_frame_prepare(dust, &s->dust, &ctx, src, err);
    orr_source_close(whole);
    for (int k = 0; k < n && !st; k++)
        views[k].dust = dust;
    if (st)
        orr_dust_frame_free(dust);
    return st;
}
