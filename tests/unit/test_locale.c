/* The library reads and writes numbers the same whatever the host
 * program's locale (core/numbers.h). The program here does what a host
 * may: setlocale(LC_ALL, "de_DE.UTF-8"), whose decimal separator is ','.
 * Then it opens a scene with "4.5" in it, reads and writes a text table,
 * writes a FITS header card, and checks that none of them saw a ','.
 *
 * The locale is made with localedef into a scratch folder (LOCPATH) when
 * the system has not generated it; the test skips (77) only when
 * localedef itself is missing. */
#include <fitsio.h>
#include <locale.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "check.h"
#include "core/numbers.h"
#include "encode/fits.h"
#include "orrery.h"
#include "scene/scene.h"
#include "source/writers/text_writer.h"
#include "tmpdir.h"

#define COMMA_LOCALE "de_DE.UTF-8"

static orr_scene g_scene;

/* Whether a program named prog is on the PATH. */
static int on_path(const char *prog)
{
    char cmd[256];
    snprintf(cmd, sizeof cmd, "command -v %s >/dev/null 2>&1", prog);
    return system(cmd) == 0;
}

/* Sets the comma locale for the whole program, generating it into
 * tmpdir/locales when needed. Exits 77 (skip) when that cannot be tried. */
static void set_comma_locale(void)
{
    if (setlocale(LC_ALL, COMMA_LOCALE))
        return;
    if (!on_path("localedef")) {
        printf("skipped: no %s locale and no localedef to make one (Debian: the locales package)\n",
               COMMA_LOCALE);
        remove_tmpdir();
        exit(77);
    }
    char dir[512], cmd[1200];
    snprintf(dir, sizeof dir, "%s/locales", tmpdir);
    snprintf(cmd, sizeof cmd, "mkdir -p %s && localedef -i de_DE -f UTF-8 %s/%s", dir, dir, COMMA_LOCALE);
    /* localedef exits 1 for mere warnings (the file is still written). */
    int rc = system(cmd);
    setenv("LOCPATH", dir, 1);
    if (!setlocale(LC_ALL, COMMA_LOCALE)) {
        fprintf(stderr, "cannot set %s even after localedef (exit status %d)\n", COMMA_LOCALE, rc);
        remove_tmpdir();
        exit(1);
    }
}

static void test_the_locale_is_set(void)
{
    CHECK(strcmp(localeconv()->decimal_point, ",") == 0);
    char buf[32];
    snprintf(buf, sizeof buf, "%g", 4.5);
    CHECK(strcmp(buf, "4,5") == 0); /* what the library must not do */
}

static void test_helpers(void)
{
    char *end;
    CHECK(orr_strtod("4.5", &end) == 4.5 && *end == '\0');
    CHECK(orr_strtod("4,5", &end) == 4.0 && *end == ','); /* ',' is not a decimal point in data */
    double v = 0;
    CHECK(orr_parse_double("-1.25e-3", &v) && v == -1.25e-3);
    CHECK(!orr_parse_double("1.5x", &v));
    char buf[64];
    orr_snprintf(buf, sizeof buf, "%g %.3f", 4.5, 0.25);
    CHECK(strcmp(buf, "4.5 0.250") == 0);
    void *saved = orr_c_locale_enter();
    snprintf(buf, sizeof buf, "%g", 4.5);
    orr_c_locale_leave(saved);
    CHECK(strcmp(buf, "4.5") == 0);
    /* The program's locale is as it set it. */
    snprintf(buf, sizeof buf, "%g", 4.5);
    CHECK(strcmp(buf, "4,5") == 0);
    orr_error err = {0};
    orr_fail(&err, ORR_ERR_USAGE, "x is %g", 4.5);
    CHECK(strcmp(err.msg, "x is 4.5") == 0);
}

/* The report of issue 19: "camera.width: expected a number, got '4.5'". */
static void test_scene(void)
{
    orr_error err = {0};
    const char *sets[] = {"camera.fov=60.5"};
    orr_scene_free(&g_scene);
    orr_status st = orr_scene_load_string(&g_scene,
                                          "input: {file: a.txt}\ncamera: {projection: perspective, fov: 4.5}\n"
                                          "image: {width: 64, height: 48}\n",
                                          "scene.yaml", tmpdir, sets, 1, &err);
    CHECK(st == ORR_OK);
    if (st)
        fprintf(stderr, "  %s\n", err.msg);
    CHECK(g_scene.projection.fov_deg == 60.5);
    orr_scene_free(&g_scene);
    st = orr_scene_load_string(&g_scene, "input: {file: a.txt}\ncamera: {projection: orthographic, width: 4.5}\n",
                               "scene.yaml", tmpdir, NULL, 0, &err);
    CHECK(st == ORR_OK);
    CHECK(g_scene.projection.ortho_width == 4.5);
    /* And through the public API, as a host program opens a scene. */
    orrery_renderer *r = NULL;
    char msg[512] = "";
    CHECK(orrery_open_yaml(&r, "input: {insitu: true}\ncamera: {projection: orthographic, width: 4.5}\n"
                               "output: {png: false}\n",
                           tmpdir, NULL, 0, msg, sizeof msg) == ORRERY_OK);
    if (!r)
        fprintf(stderr, "  %s\n", msg);
    orrery_close(r);
}

/* A table read and written back: the same numbers, with '.' in the file. */
static void test_text_table(void)
{
    char in[512], out[512];
    snprintf(in, sizeof in, "%s/in.txt", tmpdir);
    snprintf(out, sizeof out, "%s/out.txt", tmpdir);
    FILE *f = fopen(in, "w");
    fputs("x y z mass lum\n0.5 1.25 -2.5 4.5 1e-3\n", f);
    fclose(f);
    orr_error err = {0};
    orr_source *src = NULL;
    CHECK(orr_source_open_file(in, NULL, &src, &err) == ORR_OK);
    const orr_chunk *c = NULL;
    if (src && orr_source_next(src, &c, &err) == ORR_OK && c->n == 1) {
        CHECK(c->x[0] == 0.5f && c->y[0] == 1.25f && c->z[0] == -2.5f && c->mass[0] == 4.5f);
    } else {
        CHECK(!"the table was read");
        fprintf(stderr, "  %s\n", err.msg);
    }
    orr_source_close(src);
    src = NULL;
    CHECK(orr_source_open_file(in, NULL, &src, &err) == ORR_OK);
    CHECK(src && orr_text_write_source(src, out, &err) == ORR_OK);
    orr_source_close(src);
    char text[512] = "";
    f = fopen(out, "r");
    size_t got = f ? fread(text, 1, sizeof text - 1, f) : 0;
    text[got] = '\0';
    if (f)
        fclose(f);
    CHECK_CONTAINS(text, "0.5 1.25 -2.5 4.5 ");
    CHECK_CONTAINS(text, " 0.001");
    CHECK(!strchr(text, ','));
}

/* A FITS card with a double: written as 4.5 and read back as 4.5. */
static void test_fits_card(void)
{
    char path[512];
    snprintf(path, sizeof path, "%s/card.fits", tmpdir);
    float pixels[4] = {1, 2, 3, 4};
    orr_plane plane = {.width = 2, .height = 2, .data = pixels};
    orr_cards h = {0};
    orr_cards_add_double(&h, "SCALE", 4.5, "a number");
    orr_error err = {0};
    CHECK(orr_write_fits(path, &plane, 1, &h, &err) == ORR_OK);
    fitsfile *f = NULL;
    int status = 0;
    double v = 0;
    char card[FLEN_CARD] = "";
    fits_open_file(&f, path, READONLY, &status);
    fits_read_card(f, "SCALE", card, &status);
    fits_read_key(f, TDOUBLE, "SCALE", &v, NULL, &status);
    int close_status = 0;
    if (f)
        fits_close_file(f, &close_status);
    CHECK(status == 0);
    CHECK(v == 4.5);
    CHECK(strstr(card, "4.5") != NULL);
}

int main(void)
{
    make_tmpdir();
    set_comma_locale();
    test_the_locale_is_set();
    test_helpers();
    test_scene();
    test_text_table();
    test_fits_card();
    remove_tmpdir();
    return check_summary();
}
