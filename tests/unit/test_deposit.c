/* Deposits: weight is conserved, lands in the right pixels, and what falls
 * off the image is counted. */
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "splat/deposit.h"

static orr_plane make_plane(int w, int h)
{
    orr_plane p;
    orr_error err = {0};
    CHECK(orr_plane_alloc(&p, w, h, "mass", "", &err) == ORR_OK);
    return p;
}

static float at(const orr_plane *p, int i, int j)
{
    return p->data[(size_t)j * p->width + i];
}

static void deposit_one(orr_deposit_kind kind, orr_plane *p, float x, float y, float w, orr_deposit_stats *st)
{
    uint8_t vis = 1;
    orr_deposit(kind, p, 1, &x, &y, &w, &vis, NULL, st);
}

static void test_particle_at_pixel_centre(void)
{
    for (int k = 0; k < 2; k++) {
        orr_deposit_kind kind = k ? ORR_DEPOSIT_CIC : ORR_DEPOSIT_NGP;
        orr_plane p = make_plane(8, 6);
        orr_deposit_stats st = {0};
        deposit_one(kind, &p, 3.5f, 2.5f, 2.0f, &st);
        CHECK_NEAR(at(&p, 3, 2), 2.0, 0);
        CHECK_NEAR(orr_plane_sum(&p), 2.0, 0);
        CHECK_NEAR(st.deposited, 2.0, 0);
        orr_plane_free(&p);
    }
}

static void test_cic_shares(void)
{
    orr_plane p = make_plane(8, 6);
    orr_deposit_stats st = {0};
    /* At a pixel corner the four pixels get a quarter each. */
    deposit_one(ORR_DEPOSIT_CIC, &p, 4.0f, 3.0f, 1.0f, &st);
    CHECK_NEAR(at(&p, 3, 2), 0.25, 1e-7);
    CHECK_NEAR(at(&p, 4, 2), 0.25, 1e-7);
    CHECK_NEAR(at(&p, 3, 3), 0.25, 1e-7);
    CHECK_NEAR(at(&p, 4, 3), 0.25, 1e-7);
    orr_plane_free(&p);
    /* A quarter pixel right of a centre: 3/4 stays, 1/4 goes right. */
    p = make_plane(8, 6);
    deposit_one(ORR_DEPOSIT_CIC, &p, 2.75f, 1.5f, 1.0f, &st);
    CHECK_NEAR(at(&p, 2, 1), 0.75, 1e-7);
    CHECK_NEAR(at(&p, 3, 1), 0.25, 1e-7);
    CHECK_NEAR(orr_plane_sum(&p), 1.0, 1e-7);
    /* Shares in x and y multiply: (0.9, 0.1) x (0.7, 0.3). */
    orr_plane_free(&p);
    p = make_plane(8, 6);
    deposit_one(ORR_DEPOSIT_CIC, &p, 5.4f, 4.2f, 1.0f, &st);
    CHECK_NEAR(at(&p, 4, 3), 0.1 * 0.3, 1e-6);
    CHECK_NEAR(at(&p, 5, 3), 0.9 * 0.3, 1e-6);
    CHECK_NEAR(at(&p, 4, 4), 0.1 * 0.7, 1e-6);
    CHECK_NEAR(at(&p, 5, 4), 0.9 * 0.7, 1e-6);
    orr_plane_free(&p);
}

static void test_edges_count_outside_weight(void)
{
    orr_plane p = make_plane(4, 4);
    orr_deposit_stats st = {0};
    /* Half of this particle hangs off the left edge. */
    deposit_one(ORR_DEPOSIT_CIC, &p, 0.0f, 2.0f, 1.0f, &st);
    CHECK_NEAR(st.deposited, 0.5, 1e-7);
    CHECK_NEAR(st.outside, 0.5, 1e-7);
    /* Far away points (even absurdly far) count as outside, no overflow. */
    deposit_one(ORR_DEPOSIT_CIC, &p, 1e30f, -1e30f, 3.0f, &st);
    deposit_one(ORR_DEPOSIT_NGP, &p, -1e30f, 2.0f, 5.0f, &st);
    deposit_one(ORR_DEPOSIT_NGP, &p, 4.0f, 2.0f, 7.0f, &st); /* x = width is off the image */
    CHECK_NEAR(st.outside, 0.5 + 3 + 5 + 7, 1e-6);
    CHECK_NEAR(orr_plane_sum(&p), 0.5, 1e-7);
    orr_plane_free(&p);
}

static void test_mass_conserved_random(void)
{
    enum { N = 100000 };
    float *x = malloc(N * sizeof *x), *y = malloc(N * sizeof *y), *w = malloc(N * sizeof *w);
    uint8_t *vis = malloc(N);
    double total = 0, culled = 0;
    srand(11);
    for (int i = 0; i < N; i++) {
        x[i] = (float)(rand() / (double)RAND_MAX * 140 - 20); /* the image is 100 x 80 */
        y[i] = (float)(rand() / (double)RAND_MAX * 120 - 20);
        w[i] = (float)(rand() / (double)RAND_MAX);
        vis[i] = (uint8_t)(rand() % 10 != 0);
        total += w[i];
        if (!vis[i])
            culled += w[i];
    }
    for (int k = 0; k < 2; k++) {
        orr_plane p = make_plane(100, 80);
        orr_deposit_stats st = {0};
        orr_deposit(k ? ORR_DEPOSIT_CIC : ORR_DEPOSIT_NGP, &p, N, x, y, w, vis, NULL, &st);
        CHECK_NEAR(st.deposited + st.outside + st.culled, total, 1e-9 * total);
        CHECK_NEAR(st.culled, culled, 1e-9 * total);
        CHECK_NEAR(orr_plane_sum(&p), st.deposited, 1e-6 * st.deposited);
        CHECK(st.n_particles == N);
        /* About (100*80)/(140*120) of the visible weight lands in the image. */
        CHECK_NEAR(st.deposited / (total - culled), 8000.0 / 16800.0, 0.02);
        orr_plane_free(&p);
    }
    free(x);
    free(y);
    free(w);
    free(vis);
}

/* Planes are addressed with 32-bit pixel indices: 46341 x 46341 (just
 * over 2^31 pixels) is refused with a message, before any memory is
 * asked for; 46340 x 46340 passes the size check (not allocated here). */
static void test_plane_size_limit(void)
{
    orr_plane p;
    orr_error err = {0};
    CHECK(orr_plane_alloc(&p, 46341, 46341, "mass", "", &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "46341 x 46341 has more than 2^31 - 1 pixels");
    CHECK(p.data == NULL);
    CHECK(orr_plane_alloc(&p, 65536, 1, "mass", "", &err) == ORR_OK);
    orr_plane_free(&p);
}

/* The deposit's cards: the method alone for points; with kernels the
 * kernel, h_scale and the frame's lengths source in their reserved places
 * (NNEIGH only when the lengths came from the neighbours). */
static const orr_card *card(const orr_cards *h, const char *key)
{
    static const orr_card missing = {"", ORR_CARD_STRING, "(missing)", 0, 0, ""};
    for (int i = 0; i < h->n; i++)
        if (strcmp(h->cards[i].key, key) == 0)
            return &h->cards[i];
    return &missing;
}

static void test_deposit_cards(void)
{
    orr_deposit_settings d;
    orr_deposit_settings_defaults(&d);
    orr_cards *h = calloc(1, sizeof *h);
    CHECK(h != NULL);
    orr_deposit_cards(&d, 0, h);
    CHECK(h->n == 1 && strcmp(h->cards[0].key, "DEPOSIT") == 0 && strcmp(h->cards[0].str, "cic") == 0);

    memset(h, 0, sizeof *h);
    d.kind = ORR_DEPOSIT_SPH, d.kernel = ORR_KERNEL_WENDLAND_C4, d.neighbours = 16, d.h_scale = 1.5;
    orr_deposit_cards(&d, 1, h);
    const char *order[] = {"DEPOSIT", "KERNEL", "HSOURCE", "NNEIGH", "HSCALE"};
    CHECK(h->n == 5);
    for (int i = 0; i < 5 && i < h->n; i++)
        CHECK(strcmp(h->cards[i].key, order[i]) == 0);
    CHECK(strcmp(card(h, "KERNEL")->str, "wendland-c4") == 0);
    CHECK(card(h, "HSCALE")->type == ORR_CARD_DOUBLE && card(h, "HSCALE")->dbl == 1.5);
    CHECK(card(h, "HSOURCE")->type == ORR_CARD_UNSET && card(h, "NNEIGH")->type == ORR_CARD_UNSET);

    orr_cards frame = *h;
    orr_deposit_frame_cards(&d, 1, &frame);
    CHECK(strcmp(card(&frame, "HSOURCE")->str, "neighbours") == 0);
    CHECK(card(&frame, "NNEIGH")->type == ORR_CARD_LONG && card(&frame, "NNEIGH")->lng == 16);
    frame = *h;
    orr_deposit_frame_cards(&d, 0, &frame);
    CHECK(strcmp(card(&frame, "HSOURCE")->str, "file") == 0);
    CHECK(card(&frame, "NNEIGH")->type == ORR_CARD_UNSET); /* dropped from the frame's files */
    free(h);
}

int main(void)
{
    RUN(test_particle_at_pixel_centre);
    RUN(test_cic_shares);
    RUN(test_edges_count_outside_weight);
    RUN(test_mass_conserved_random);
    RUN(test_plane_size_limit);
    RUN(test_deposit_cards);
    return check_summary();
}
