#include <math.h>
#include <string.h>

#include "check.h"
#include "post/colormap.h"

/* First, second and last entries of matplotlib's tables (_cm_listed.py). */
static const float magma_first[3] = {0.001462f, 0.000466f, 0.013866f};
static const float magma_second[3] = {0.002258f, 0.001295f, 0.018331f};
static const float magma_last[3] = {0.987053f, 0.991438f, 0.749504f};
static const float magma_128[3] = {0.716387f, 0.214982f, 0.475290f};
static const float inferno_first[3] = {0.001462f, 0.000466f, 0.013866f};
static const float inferno_last[3] = {0.988362f, 0.998364f, 0.644924f};
static const float inferno_128[3] = {0.735683f, 0.215906f, 0.330245f};

static void check_rgb(orr_colormap_kind kind, float t, const float expect[3], double tol)
{
    float rgb[3] = {-1, -1, -1};
    orr_colormap_lookup(kind, t, rgb);
    for (int c = 0; c < 3; c++)
        CHECK_NEAR(rgb[c], expect[c], tol);
}

static void test_names(void)
{
    orr_colormap_kind k = ORR_CMAP_MAGMA;
    CHECK(orr_colormap_from_name("grey", &k) && k == ORR_CMAP_GREY);
    k = ORR_CMAP_MAGMA;
    CHECK(orr_colormap_from_name("gray", &k) && k == ORR_CMAP_GREY);
    CHECK(orr_colormap_from_name("magma", &k) && k == ORR_CMAP_MAGMA);
    CHECK(orr_colormap_from_name("inferno", &k) && k == ORR_CMAP_INFERNO);
    CHECK(!orr_colormap_from_name("viridis", &k));
    CHECK(!orr_colormap_from_name("", &k));
    CHECK(!orr_colormap_from_name(NULL, &k));
    char list[64];
    for (int i = ORR_CMAP_GREY; i <= ORR_CMAP_INFERNO; i++) {
        const char *name = orr_colormap_name((orr_colormap_kind)i);
        CHECK(orr_colormap_from_name(name, &k) && (int)k == i);
        CHECK_CONTAINS(orr_named_list(orr_colormap_kind_names, list, sizeof list), name);
    }
    /* The alias is read but not offered. */
    CHECK(strcmp(orr_named_list(orr_colormap_kind_names, list, sizeof list), "grey magma inferno") == 0);
}

static void test_grey(void)
{
    const float quarter[3] = {0.25f, 0.25f, 0.25f}, zero[3] = {0, 0, 0}, one[3] = {1, 1, 1};
    check_rgb(ORR_CMAP_GREY, 0.25f, quarter, 0);
    check_rgb(ORR_CMAP_GREY, 0.0f, zero, 0);
    check_rgb(ORR_CMAP_GREY, 1.0f, one, 0);
    check_rgb(ORR_CMAP_GREY, -3.0f, zero, 0);
    check_rgb(ORR_CMAP_GREY, 7.0f, one, 0);
    check_rgb(ORR_CMAP_GREY, NAN, zero, 0);
}

static void test_table_entries(void)
{
    check_rgb(ORR_CMAP_MAGMA, 0.0f, magma_first, 0);
    check_rgb(ORR_CMAP_MAGMA, 1.0f, magma_last, 1e-7);
    check_rgb(ORR_CMAP_MAGMA, 1.0f / 255.0f, magma_second, 1e-6);
    check_rgb(ORR_CMAP_MAGMA, 128.0f / 255.0f, magma_128, 1e-6);
    check_rgb(ORR_CMAP_INFERNO, 0.0f, inferno_first, 0);
    check_rgb(ORR_CMAP_INFERNO, 1.0f, inferno_last, 1e-7);
    check_rgb(ORR_CMAP_INFERNO, 128.0f / 255.0f, inferno_128, 1e-6);
}

static void test_interpolation(void)
{
    float mid[3];
    for (int c = 0; c < 3; c++)
        mid[c] = 0.5f * (magma_first[c] + magma_second[c]);
    check_rgb(ORR_CMAP_MAGMA, 0.5f / 255.0f, mid, 1e-6);
    float quarter[3];
    for (int c = 0; c < 3; c++)
        quarter[c] = 0.75f * magma_first[c] + 0.25f * magma_second[c];
    check_rgb(ORR_CMAP_MAGMA, 0.25f / 255.0f, quarter, 1e-6);
}

static void test_clamping_and_nan(void)
{
    const orr_colormap_kind kinds[] = {ORR_CMAP_MAGMA, ORR_CMAP_INFERNO};
    for (int i = 0; i < 2; i++) {
        float lo[3], hi[3];
        orr_colormap_lookup(kinds[i], 0.0f, lo);
        orr_colormap_lookup(kinds[i], 1.0f, hi);
        check_rgb(kinds[i], -0.5f, lo, 0);
        check_rgb(kinds[i], -INFINITY, lo, 0);
        check_rgb(kinds[i], NAN, lo, 0);
        check_rgb(kinds[i], 1.5f, hi, 0);
        check_rgb(kinds[i], INFINITY, hi, 0);
    }
}

/* Perceptual maps get lighter all the way: luminance rises with t. */
static void test_monotone_lightness(void)
{
    const orr_colormap_kind kinds[] = {ORR_CMAP_MAGMA, ORR_CMAP_INFERNO, ORR_CMAP_GREY};
    for (int i = 0; i < 3; i++) {
        double prev = -1;
        int rising = 1;
        for (int s = 0; s <= 1000; s++) {
            float rgb[3];
            orr_colormap_lookup(kinds[i], (float)s / 1000.0f, rgb);
            double lum = 0.2126 * rgb[0] + 0.7152 * rgb[1] + 0.0722 * rgb[2];
            if (!(lum > prev))
                rising = 0;
            for (int c = 0; c < 3; c++)
                if (!(rgb[c] >= 0 && rgb[c] <= 1))
                    rising = 0;
            prev = lum;
        }
        CHECK(rising);
    }
}

int main(void)
{
    RUN(test_names);
    RUN(test_grey);
    RUN(test_table_entries);
    RUN(test_interpolation);
    RUN(test_clamping_and_nan);
    RUN(test_monotone_lightness);
    return check_summary();
}
