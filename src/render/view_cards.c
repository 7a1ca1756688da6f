/* A view's FITS cards (core/cards.h), made once by the plan and filled in
 * each frame: each stage's own cards (orr_projection_cards,
 * orr_view_psf_cards, orr_observer_cards, ...), from its settings and what
 * it prepared, are added when the view is planned, and the cards whose
 * values each frame gives (the camera, the counts, the time, the frame
 * number) are reserved in their places. Each frame's header is begun from
 * them by encode/ (orr_wcs_frame_cards), with the world coordinates, which
 * follow the camera; here the frame then sets the reserved values, drops
 * the ones it has none for (a periodic box's when it draws no copies, the
 * frame number of a still) and adds the stereo cards. Every FITS file of
 * the frame (and an in-situ keeper) gets that header. */
#include "render/view_state.h"

#include <string.h>

#include "encode/wcs.h"
#include "scene/scene_output.h"

/* A card each frame gives the value of. */
typedef struct reserved {
    const char *key, *comment;
} reserved;

static void reserve(orr_cards *h, const reserved *cards, size_t n)
{
    for (size_t i = 0; i < n; i++)
        orr_cards_reserve(h, cards[i].key, cards[i].comment);
}

/* The counts of the frame's report, and its time and source. */
static void plan_report_cards(const view_state *v, const orr_input_settings *input, orr_cards *h)
{
    orr_input_cards(input, h);
    static const reserved counts[] = {
        {"NPART", "particles read"},
        {"NSELECT", "particles of the selected types"},
        {"NSKIPPED", "particles skipped as non-finite"},
        {"NCULLED", "particles not drawn (out of view)"},
        {"PERBOX", "periodic box side, drawn in copies"},
        {"NREPLIC", "copies of the periodic box drawn"},
        {"NBLKCULL", "copies of blocks culled out of view"},
        {"WIMAGE", "weight deposited in the image"},
        {"WOUTSIDE", "weight that fell off the image"},
    };
    static const reserved when[] = {
        {"SIMTIME", "simulation time of the snapshot"},
        {"FRAME", "frame number (0-based)"},
        {"NFRAMES", "frames in the run"},
        {"SOURCE", "particle source"},
    };
    reserve(h, counts, sizeof counts / sizeof counts[0]);
    orr_colour_cards(&v->files.colour, h);
    reserve(h, when, sizeof when / sizeof when[0]);
}

/* Each stage's cards, in the order the files have always had them. */
void orr_view_plan_cards(view_state *v, const orr_input_settings *input, const orr_observer_settings *observer)
{
    const view_camera_plan *c = &v->camera_plan;
    orr_cards *h = &v->cards;
    memset(h, 0, sizeof *h);
    orr_cards_add_string(h, "CREATOR", "orrery " ORRERY_VERSION, "software that made this file");
    orr_cards_add_string(h, "ORRVERS", ORRERY_VERSION, "orrery version");
    /* (a stereo eye's shift changes none of the projection's cards) */
    orr_projection_cards(&v->pass.proj, h);
    orr_camera_dome_cards(&c->camera, v->pass.proj.settings.kind, h);
    static const reserved camera[] = {
        {"CAMPOSX", "camera position x"},
        {"CAMPOSY", "camera position y"},
        {"CAMPOSZ", "camera position z"},
        {"CAMQW", "camera-to-world quaternion w"},
        {"CAMQX", "camera-to-world quaternion x"},
        {"CAMQY", "camera-to-world quaternion y"},
        {"CAMQZ", "camera-to-world quaternion z"},
    };
    reserve(h, camera, sizeof camera / sizeof camera[0]);
    orr_cards_add_long(h, "IMGWIDTH", v->pass.proj.width, "[pixel] image width");
    orr_cards_add_long(h, "IMGHEIGH", v->pass.proj.height, "[pixel] image height");
    orr_deposit_cards(&v->pass.splat.deposit, v->pass.use_sph, h);
    orr_view_psf_cards(&v->pass.psf, h);
    plan_report_cards(v, input, h);
    if (observer->has_id) /* an observer's dimming is the observer's; without one, the camera's */
        orr_observer_cards(observer, h);
    else
        orr_camera_dim_cards(&c->camera, h);
    memset(&v->stereo_cards, 0, sizeof v->stereo_cards);
    if (c->stereo.mode) {
        orr_stereo_cards(&c->stereo, c->kind, &v->stereo_cards);
        if (c->stereo.mode == ORR_STEREO_ANAGLYPH)
            orr_picture_anaglyph_cards(&v->files.picture, &v->stereo_cards);
    }
}

/* The frame's values of the reserved cards. */
static void set_frame_values(const view_state *v, orr_cards *h)
{
    const orr_render_report *rep = v->rep;
    const orr_camera *cam = &rep->camera;
    orr_cards_set_double(h, "CAMPOSX", cam->position.x);
    orr_cards_set_double(h, "CAMPOSY", cam->position.y);
    orr_cards_set_double(h, "CAMPOSZ", cam->position.z);
    orr_cards_set_double(h, "CAMQW", cam->orientation.w);
    orr_cards_set_double(h, "CAMQX", cam->orientation.x);
    orr_cards_set_double(h, "CAMQY", cam->orientation.y);
    orr_cards_set_double(h, "CAMQZ", cam->orientation.z);
    orr_deposit_frame_cards(&v->pass.splat.deposit, v->pass.lengths != NULL, h);
    if (v->pass.psf.sky)
        orr_cards_set_long(h, "PSFSTARS", v->pass.psf.sky->stars_drawn);
    orr_cards_set_long(h, "NPART", (long long)rep->n_read);
    orr_cards_set_long(h, "NSELECT", (long long)rep->n_selected);
    orr_cards_set_long(h, "NSKIPPED", (long long)rep->n_nonfinite);
    orr_cards_set_long(h, "NCULLED", (long long)rep->deposit.n_culled);
    if (rep->n_replicas) {
        orr_cards_set_double(h, "PERBOX", v->pass.periodic.box);
        orr_cards_set_long(h, "NREPLIC", rep->n_replicas);
        orr_cards_set_long(h, "NBLKCULL", (long long)rep->n_blocks_culled);
    }
    orr_cards_set_double(h, "WIMAGE", rep->deposit.deposited);
    orr_cards_set_double(h, "WOUTSIDE", rep->deposit.outside);
    orr_cards_set_double(h, "YIMAGE", rep->deposit_y.deposited);
    orr_cards_set_double(h, "YOUTSIDE", rep->deposit_y.outside);
    orr_cards_set_double(h, "SIMTIME", rep->sim_time);
    if (rep->nframes > 1) {
        orr_cards_set_long(h, "FRAME", rep->frame);
        orr_cards_set_long(h, "NFRAMES", rep->nframes);
    }
    const char *slash = strrchr(rep->source, '/');
    orr_cards_set_string(h, "SOURCE", slash ? slash + 1 : rep->source);
    orr_cards_set_double(h, "NORMX", rep->sky.z.x);
    orr_cards_set_double(h, "NORMY", rep->sky.z.y);
    orr_cards_set_double(h, "NORMZ", rep->sky.z.z);
}

void orr_view_frame_cards(view_state *v)
{
    const orr_render_report *rep = v->rep;
    orr_cards *h = &v->frame_cards;
    orr_wcs_view wcs = {&v->pass.proj, &rep->camera, &rep->sky, rep->has_sky_frame, v->length_unit};
    /* The world coordinates' cards come with values: none is a place that
     * set_frame_values fills, so they may go in first. */
    orr_wcs_frame_cards(h, &v->cards, &wcs);
    set_frame_values(v, h);
    orr_cards_append(h, &v->stereo_cards);
    orr_cards_set_double(h, "CONVERG", rep->stereo_convergence);
    orr_cards_drop_unset(h);
    h->scene = v->files.scene_yaml; /* every FITS file says how it was made */
}
