/* A view's FITS cards (encode/fits.h), made once by the plan and filled in
 * each frame: what depends on the scene, the projection and the PSF is
 * written when the view is planned, and the cards whose values each frame
 * gives (the camera, the counts, the time, the frame number) are reserved
 * in their places; each frame copies them, sets those, drops the ones the
 * frame has none for (a periodic box's when it draws no copies, the frame
 * number of a still), and adds the world coordinates, which follow the
 * camera, and the stereo cards. Every FITS file of the frame (and an
 * in-situ keeper) gets that copy. */
#include "render/view_state.h"

#include <string.h>

#include "encode/wcs.h"
#include "scene/scene_output.h"

/* A card each frame gives the value of. */
typedef struct reserved {
    const char *key, *comment;
} reserved;

static void reserve(orr_fits_header *h, const reserved *cards, size_t n)
{
    for (size_t i = 0; i < n; i++)
        orr_fits_reserve(h, cards[i].key, cards[i].comment);
}

/* The projection's cards: its kind and the parameters the scene gave it. */
static void plan_projection_cards(const view_state *v, orr_fits_header *h)
{
    const orr_scene *s = v->scene;
    const orr_projection *p = &v->base_proj; /* (a stereo eye's shift changes none of these) */
    orr_fits_add_string(h, "PROJTYPE", orr_projection_name(p->kind), "projection");
    if (p->kind == ORR_PROJ_ORTHOGRAPHIC)
        orr_fits_add_double(h, "ORTHOWID", p->ortho_width, "image width in simulation length units");
    if (p->kind == ORR_PROJ_PERSPECTIVE) {
        orr_fits_add_double(h, "FOV", p->fov_deg, "[deg] field of view along the wider axis");
        orr_fits_add_double(h, "NEAR", p->near, "near plane distance");
    }
    if (p->kind == ORR_PROJ_DOME) {
        orr_fits_add_double(h, "DOMEFOV", p->dome_fov_deg, "[deg] dome field of view");
        orr_fits_add_double(h, "DOMETILT", s->camera.dome_tilt, "[deg] dome tilt toward the front");
        if (s->camera.dome[0])
            orr_fits_add_string(h, "DOMEPROF", s->camera.dome, "dome profile");
    }
}

/* The deposit's and the PSF's cards. */
static void plan_deposit_cards(const view_state *v, orr_fits_header *h)
{
    const orr_scene *s = v->scene;
    const orr_projection *p = &v->base_proj;
    orr_fits_add_string(h, "DEPOSIT", orr_deposit_name(s->deposit.kind), "deposit method");
    if (v->use_sph) {
        orr_fits_add_string(h, "KERNEL", orr_kernel_name(s->deposit.kernel), "SPH kernel (support 2h)");
        orr_fits_reserve(h, "HSOURCE", "where smoothing lengths came from");
        orr_fits_reserve(h, "NNEIGH", "h = half the distance to this neighbour");
        orr_fits_add_double(h, "HSCALE", s->deposit.h_scale, "smoothing lengths multiplied by this");
    }
    orr_fits_add_string(h, "PSF", orr_named_name(orr_psf_kind_names, (int)s->psf.kind), "point spread function");
    if (s->psf.kind == ORR_PSF_GAUSSIAN && orr_projection_is_sky(p))
        orr_fits_add_double(h, "PSFFWHM", v->psf.core_fwhm_arcmin, "[arcmin] PSF FWHM on the sky");
    else if (s->psf.kind == ORR_PSF_GAUSSIAN)
        orr_fits_add_double(h, "PSFFWHM", s->psf.fwhm, "[pixel] PSF FWHM");
    else if (s->psf.kind != ORR_PSF_NONE)
        orr_fits_add_double(h, "PSFSCALE", s->psf.arcsec_per_pixel, "[arcsec/pixel] image scale for the PSF");
    if (v->psf.core) {
        orr_fits_add_double(h, "PSFFWHM", s->psf.fwhm, "[pixel] the PSF core's FWHM");
        orr_fits_add_double(h, "PSFMAG", v->psf.sky->rad_per_pixel, "image pixels per PSF pixel");
        orr_fits_reserve(h, "PSFSTARS", "stars drawn with the whole PSF");
    } else if (v->psf.sky) {
        orr_fits_add_double(h, "PSFFWHM", v->psf.core_fwhm_arcmin, "[arcmin] the PSF core's FWHM on the sky");
        orr_fits_add_double(h, "PSFSKYSC", v->psf.sky->rad_per_pixel * (180.0 * 3600.0 / ORR_PI),
                            "[arcsec] one PSF pixel on the sky");
        orr_fits_reserve(h, "PSFSTARS", "stars drawn with the whole PSF");
    }
}

/* The counts of the frame's report, and its time and source. */
static void plan_report_cards(const view_state *v, orr_fits_header *h)
{
    const orr_scene *s = v->scene;
    orr_fits_add_string(h, "WEIGHT", s->input.weight, "particle field deposited");
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
    if (s->colour.has_populations) {
        orr_fits_add_long(h, "NPOPS", s->colour.populations.n, "colour populations");
        orr_fits_reserve(h, "YIMAGE", "luminance Y deposited in the image");
        orr_fits_reserve(h, "YOUTSIDE", "luminance Y that fell off the image");
    }
    reserve(h, when, sizeof when / sizeof when[0]);
}

/* The observer's frame, and the dimming with distance. */
static void plan_observer_cards(const view_state *v, orr_fits_header *h)
{
    const orr_scene *s = v->scene;
    if (s->observer.has_id) {
        orr_fits_add_long(h, "OBSID", (long long)s->observer.id, "observer particle id");
        orr_fits_add_long(h, "REFID", (long long)s->observer.reference_id, "reference particle id (l = 0)");
        orr_fits_reserve(h, "NORMX", "disc normal n0 (b = 90) x");
        orr_fits_reserve(h, "NORMY", "disc normal n0 (b = 90) y");
        orr_fits_reserve(h, "NORMZ", "disc normal n0 (b = 90) z");
        orr_fits_add_bool(h, "DIMMED", s->observer.dim, "weights divided by r^2 from the observer");
    } else if (s->camera.dim) {
        orr_fits_add_bool(h, "DIMMED", 1, "weights divided by r^2 from the camera");
    }
}

void orr_view_plan_cards(view_state *v)
{
    orr_fits_header *h = &v->cards;
    memset(h, 0, sizeof *h);
    orr_fits_add_string(h, "CREATOR", "orrery " ORRERY_VERSION, "software that made this file");
    orr_fits_add_string(h, "ORRVERS", ORRERY_VERSION, "orrery version");
    plan_projection_cards(v, h);
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
    orr_fits_add_long(h, "IMGWIDTH", v->base_proj.width, "[pixel] image width");
    orr_fits_add_long(h, "IMGHEIGH", v->base_proj.height, "[pixel] image height");
    plan_deposit_cards(v, h);
    plan_report_cards(v, h);
    plan_observer_cards(v, h);
    memset(&v->stereo_cards, 0, sizeof v->stereo_cards);
    if (v->scene->stereo.mode)
        orr_stereo_add_cards(&v->stereo_cards, v->scene);
}

/* The frame's values of the reserved cards. */
static void set_frame_values(const view_state *v, orr_fits_header *h)
{
    const orr_scene *s = v->scene;
    const orr_render_report *rep = v->rep;
    const orr_camera *cam = &rep->camera;
    orr_fits_set_double(h, "CAMPOSX", cam->position.x);
    orr_fits_set_double(h, "CAMPOSY", cam->position.y);
    orr_fits_set_double(h, "CAMPOSZ", cam->position.z);
    orr_fits_set_double(h, "CAMQW", cam->orientation.w);
    orr_fits_set_double(h, "CAMQX", cam->orientation.x);
    orr_fits_set_double(h, "CAMQY", cam->orientation.y);
    orr_fits_set_double(h, "CAMQZ", cam->orientation.z);
    orr_fits_set_string(h, "HSOURCE", v->lengths ? "neighbours" : "file");
    if (v->lengths)
        orr_fits_set_long(h, "NNEIGH", s->deposit.neighbours);
    if (v->psf.sky)
        orr_fits_set_long(h, "PSFSTARS", v->psf.sky->stars_drawn);
    orr_fits_set_long(h, "NPART", (long long)rep->n_read);
    orr_fits_set_long(h, "NSELECT", (long long)rep->n_selected);
    orr_fits_set_long(h, "NSKIPPED", (long long)rep->n_nonfinite);
    orr_fits_set_long(h, "NCULLED", (long long)rep->deposit.n_culled);
    if (rep->n_replicas) {
        orr_fits_set_double(h, "PERBOX", v->periodic.box);
        orr_fits_set_long(h, "NREPLIC", rep->n_replicas);
        orr_fits_set_long(h, "NBLKCULL", (long long)rep->n_blocks_culled);
    }
    orr_fits_set_double(h, "WIMAGE", rep->deposit.deposited);
    orr_fits_set_double(h, "WOUTSIDE", rep->deposit.outside);
    orr_fits_set_double(h, "YIMAGE", rep->deposit_y.deposited);
    orr_fits_set_double(h, "YOUTSIDE", rep->deposit_y.outside);
    orr_fits_set_double(h, "SIMTIME", rep->sim_time);
    if (rep->nframes > 1) {
        orr_fits_set_long(h, "FRAME", rep->frame);
        orr_fits_set_long(h, "NFRAMES", rep->nframes);
    }
    const char *slash = strrchr(rep->source, '/');
    orr_fits_set_string(h, "SOURCE", slash ? slash + 1 : rep->source);
    orr_fits_set_double(h, "NORMX", rep->sky.z.x);
    orr_fits_set_double(h, "NORMY", rep->sky.z.y);
    orr_fits_set_double(h, "NORMZ", rep->sky.z.z);
}

void orr_view_frame_cards(view_state *v)
{
    const orr_scene *s = v->scene;
    const orr_render_report *rep = v->rep;
    orr_fits_header *h = &v->frame_cards;
    *h = v->cards;
    set_frame_values(v, h);
    orr_wcs_view wcs = {&v->proj, &rep->camera, &rep->sky, rep->has_sky_frame, v->length_unit};
    orr_wcs_add_cards(h, &wcs);
    orr_fits_append(h, &v->stereo_cards);
    orr_fits_set_double(h, "CONVERG", rep->stereo_convergence);
    orr_fits_drop_unset(h);
    h->scene = s->scene_yaml; /* every FITS file says how it was made */
}
