#include "scene/scene_output.h"

#include <string.h>

/* A pair's picture (anaglyph, side by side, over-under) has no one map
 * outline to cut out; separate eyes are each a view's own picture (spans
 * the output and the stereo pair). */
static orr_status check_alpha_mask(const orr_scene *s, const scene_marks *m, orr_error *err)
{
    int pair = s->stereo.mode != ORR_STEREO_NONE && s->stereo.mode != ORR_STEREO_SEPARATE;
    if (s->output.alpha_mask && pair)
        return scene_fail_key(s, m, "output.alpha_mask", err,
                              "output.alpha_mask: not with stereo.mode %s (one picture of both eyes); use "
                              "stereo.mode: separate for an alpha per eye",
                              orr_stereo_mode_name(s->stereo.mode));
    return ORR_OK;
}

/* An EXR channel name's part between dots: OpenEXR allows any bytes but
 * compositors split layers at '.', and shells, Nuke's and Blender's
 * expressions read names best as letters, digits, '_' and '-'. */
static int is_layer_name(const char *name)
{
    return name[0] && strspn(name, "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_-") ==
                          strlen(name);
}

/* output.exr_population_layers needs populations to split the X, Y, Z
 * planes into, and the linear EXR to hold them; each population's name
 * becomes its layer's, NAME.R ..., which may not be the EXR's own layers
 * (spans the output, the colour populations and stereo). */
static orr_status check_population_layers(const orr_scene *s, const scene_marks *m, orr_error *err)
{
    static const char key[] = "output.exr_population_layers";
    if (!s->output.exr_population_layers)
        return ORR_OK;
    if (!s->colour.has_populations || s->colour.populations.n == 0)
        return scene_fail_key(s, m, key, err, "%s: needs colour.populations, whose Y it splits into layers", key);
    if (!s->output.write_exr)
        return scene_fail_key(s, m, key, err, "%s: needs output.exr: true, the file that holds the layers", key);
    if (s->stereo.mode != ORR_STEREO_NONE)
        return scene_fail_key(s, m, key, err, "%s: not with stereo.mode %s (a view's planes only)", key,
                              orr_stereo_mode_name(s->stereo.mode));
    if (s->colour.populations.n > ORR_POPULATION_LAYERS_MAX)
        return scene_fail_key(s, m, key, err, "%s: at most %d populations, the scene has %d", key,
                              ORR_POPULATION_LAYERS_MAX, s->colour.populations.n);
    for (int i = 0; i < s->colour.populations.n; i++) {
        const char *name = s->colour.populations.pop[i].name;
        if (!is_layer_name(name))
            return scene_fail_key(s, m, key, err,
                                  "%s: population '%s' cannot name the layer %s.R: a layer name holds only "
                                  "letters, digits, '_' and '-'",
                                  key, name, name);
        if (strcmp(name, "xyz") == 0 || strcmp(name, "extinction") == 0)
            return scene_fail_key(s, m, key, err, "%s: population '%s' would name its layer as the EXR's own "
                                  "layer %s; rename the population", key, name, name);
    }
    return ORR_OK;
}

orr_status scene_check_output_keys(const orr_scene *s, const scene_marks *m, orr_error *err)
{
    orr_status st = check_alpha_mask(s, m, err);
    return st ? st : check_population_layers(s, m, err);
}


const char *scene_weight_unit(const orr_scene *s, const char *file_mass)
{
    if (s->output.bunit[0])
        return s->output.bunit;
    int weighs_mass = strcmp(s->input.weight, "mass") == 0 && !s->colour.has_populations && !s->compose.nlayers;
    if (!weighs_mass)
        return "";
    if (s->input.model.name[0])
        return "10**10 solMass";
    return file_mass ? file_mass : "";
}

const char *scene_length_unit(const orr_scene *s, const char *file_length)
{
    if (s->output.length_unit[0])
        return s->output.length_unit;
    if (s->input.model.name[0])
        return "kpc";
    return file_length ? file_length : "";
}

/* A key that a HEALPix map cannot honour, and why. */
static orr_status healpix_refuses(const orr_scene *s, const scene_marks *m, const char *key, const char *why,
                                  orr_error *err)
{
    return scene_fail_key(s, m, key, err, "%s: not with camera.projection: healpix (%s)", key, why);
}

orr_status scene_check_healpix(orr_scene *s, const scene_marks *m, orr_error *err)
{
    if (s->projection.kind != ORR_PROJ_HEALPIX) {
        static const char *const keys[] = {"camera.healpix_nside", "camera.healpix_order"};
        for (int i = 0; i < 2; i++)
            if (scene_mark(m, keys[i]))
                return scene_fail_key(s, m, keys[i], err, "%s: only with camera.projection: healpix", keys[i]);
        return ORR_OK;
    }
    /* (camera.healpix_nside's power of 2 is the projection's to check:
     * orr_projection_prepare) */
    if (s->deposit.kind != ORR_DEPOSIT_NGP && s->deposit.kind != ORR_DEPOSIT_SPH)
        return scene_fail_key(s, m, scene_mark(m, "deposit") ? "deposit" : "camera.projection", err,
                              "camera.projection: healpix takes deposit: ngp (each particle whole into the pixel "
                              "its direction falls in) or sph (each kernel integrated over the pixels it "
                              "covers), not %s",
                              orr_deposit_name(s->deposit.kind));
    static const char *const image_keys[] = {"image.width", "image.height"};
    for (int i = 0; i < 2; i++)
        if (scene_mark(m, image_keys[i]))
            return healpix_refuses(s, m, image_keys[i], "camera.healpix_nside sets the map's size", err);
    if (s->psf.kind != ORR_PSF_NONE)
        return healpix_refuses(s, m, "psf.kind", "a PSF needs a picture's neighbouring pixels", err);
    if (scene_mark(m, "camera.lon_flip"))
        return healpix_refuses(s, m, "camera.lon_flip", "HEALPix's longitude phi grows eastward by definition", err);
    if (s->stereo.mode != ORR_STEREO_NONE)
        return healpix_refuses(s, m, "stereo.mode", "one map of the whole sky has no eyes", err);
    /* The map is a table of pixels, not a picture: only FITS. A picture
     * turned off (output.exr: false, as the Python package sets) asks for
     * nothing the map cannot give. */
    static const char *const picture_keys[] = {"output.image", "compose.layers"};
    for (int i = 0; i < 2; i++)
        if (scene_mark(m, picture_keys[i]))
            return healpix_refuses(s, m, picture_keys[i], "its map is a FITS table of pixels, not a picture", err);
    const struct {
        const char *key;
        int on;
    } pictures[] = {{"output.exr", s->output.write_exr}, {"output.raw", s->output.write_raw},
                    {"output.png", s->output.write_png}};
    for (int i = 0; i < 3; i++)
        if (pictures[i].on && scene_mark(m, pictures[i].key))
            return healpix_refuses(s, m, pictures[i].key, "its map is a FITS table of pixels, not a picture", err);
    s->output.write_png = 0;
    s->projection.width = 4 * s->projection.healpix_nside;
    s->projection.height = 3 * s->projection.healpix_nside;
    return ORR_OK;
}
