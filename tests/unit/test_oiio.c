/* Output through OpenImageIO (src/encode/oiio.cpp) and the writer chosen by
 * extension (src/encode/image_out.c): TIFF 16-bit and float round trips with
 * their metadata, JPEG, unknown extensions and unwritable folders. */
#include <dirent.h>
#include <math.h>
#include <stdlib.h>
#include <unistd.h>

#include "tmpdir.h"
#include "check.h"
#include "encode/image_out.h"
#include "encode/oiio.h"

enum { W = 6, H = 4 };

/* Values in [0, 1] on a fine grid, plus the edge cases of quantisation. */
static void fill_rgb(float *rgb)
{
    for (int i = 0; i < W * H * 3; i++)
        rgb[i] = (float)fmod(i * 0.1234567, 1.0);
    rgb[0] = 0.0f;
    rgb[1] = 1.0f;
    rgb[2] = 0.6f / 65535; /* between codes 0 and 1, nearer 1 */
    rgb[3] = -0.25f;       /* clipped to 0 */
    rgb[4] = 1.5f;         /* clipped to 1 */
    rgb[5] = NAN;          /* becomes 0 */
}

static float clip01(float v)
{
    return v > 0 ? (v < 1 ? v : 1) : 0;
}

static void get_attr(const char *path, const char *name, char *buf, size_t size)
{
    orr_error err;
    orr_error_clear(&err);
    if (orr_oiio_get_attribute(path, name, buf, size, &err) != ORR_OK) {
        fprintf(stderr, "attribute %s: %s\n", name, err.msg);
        buf[0] = '\0';
    }
}

static orr_image_meta test_meta(void)
{
    orr_image_meta m = {0};
    m.scene = "future-sky";
    m.projection = "dome";
    m.has_frame = 1;
    m.frame = 7;
    m.has_time = 1;
    m.time = 13.75;
    return m;
}

static void test_tiff16_round_trip(void)
{
    make_tmpdir();
    char path[512];
    snprintf(path, sizeof path, "%s/frame.tif", tmpdir);
    float rgb[W * H * 3];
    fill_rgb(rgb);
    orr_image_meta m = test_meta();
    orr_error err;
    orr_error_clear(&err);
    CHECK(orr_write_oiio(path, rgb, W, H, 3, 16, &m, &err) == ORR_OK);
    CHECK(count_entries() == 1);

    float *px = NULL;
    int w = 0, h = 0, n = 0;
    CHECK(orr_read_oiio(path, &px, &w, &h, &n, &err) == ORR_OK);
    CHECK(w == W && h == H && n == 3);
    int bad = 0;
    for (int i = 0; px && n == 3 && i < W * H * 3; i++) {
        float want = rgb[i] == rgb[i] ? clip01(rgb[i]) : 0;
        bad += !(fabsf(px[i] - want) <= 0.5f / 65535 + 1e-7f);
    }
    CHECK(bad == 0);
    CHECK(px && px[2] == 1.0f / 65535);
    free(px);

    char buf[1024];
    get_attr(path, "format", buf, sizeof buf);
    CHECK(strcmp(buf, "uint16") == 0);
    get_attr(path, "oiio:BitsPerSample", buf, sizeof buf);
    CHECK(strcmp(buf, "16") == 0);
    get_attr(path, "ImageDescription", buf, sizeof buf);
    CHECK(strcmp(buf, "software=orrery " ORRERY_VERSION "\nscene=future-sky\nframe=7\ntime=13.75\n"
                      "projection=dome") == 0);
    get_attr(path, "Software", buf, sizeof buf);
    CHECK(strcmp(buf, "orrery " ORRERY_VERSION) == 0);
    get_attr(path, "DocumentName", buf, sizeof buf);
    CHECK(strcmp(buf, "future-sky") == 0);
    remove_tmpdir();
}

/* Linear planes as a float TIFF come back unchanged (TIFF keeps no channel
 * names); OpenEXR written through OpenImageIO keeps the names too. */
static void test_tiff_float_named_planes(void)
{
    make_tmpdir();
    char path[512];
    snprintf(path, sizeof path, "%s/planes.tiff", tmpdir);
    orr_plane p[2];
    orr_error err;
    orr_error_clear(&err);
    CHECK(orr_plane_alloc(&p[0], W, H, "mass", "", &err) == ORR_OK);
    CHECK(orr_plane_alloc(&p[1], W, H, "Y", "", &err) == ORR_OK);
    for (int i = 0; i < W * H; i++) {
        p[0].data[i] = (float)(i * 1e7 + 0.3); /* linear data: no clipping */
        p[1].data[i] = -(float)i / 3.0f;
    }
    CHECK(orr_write_image_planes(path, p, 2, NULL, &err) == ORR_OK);
    orr_plane *back = NULL;
    int n = 0;
    CHECK(orr_read_oiio_planes(path, &back, &n, &err) == ORR_OK);
    CHECK(n == 2);
    if (n == 2) {
        int bad = 0;
        for (int i = 0; i < W * H; i++)
            bad += back[0].data[i] != p[0].data[i] || back[1].data[i] != p[1].data[i];
        CHECK(bad == 0);
    }
    for (int i = 0; i < n; i++)
        orr_plane_free(&back[i]);
    free(back);
    char buf[64];
    get_attr(path, "format", buf, sizeof buf);
    CHECK(strcmp(buf, "float") == 0);

    snprintf(path, sizeof path, "%s/planes-oiio.exr", tmpdir);
    float px[W * H * 2];
    for (int i = 0; i < W * H; i++) {
        px[2 * i] = p[0].data[i];
        px[2 * i + 1] = p[1].data[i];
    }
    const char *names[2] = {"mass", "Y"};
    CHECK(orr_write_oiio_named(path, px, W, H, 2, names, 32, NULL, &err) == ORR_OK);
    back = NULL;
    n = 0;
    CHECK(orr_read_oiio_planes(path, &back, &n, &err) == ORR_OK);
    CHECK(n == 2);
    for (int k = 0; k < n; k++) {
        int c = !strcmp(back[k].name, "mass") ? 0 : !strcmp(back[k].name, "Y") ? 1 : -1;
        CHECK(c >= 0);
        CHECK(c >= 0 && back[k].data[5] == p[c].data[5]);
        orr_plane_free(&back[k]);
    }
    free(back);
    orr_plane_free(&p[0]);
    orr_plane_free(&p[1]);
    remove_tmpdir();
}

/* JPEG is lossy: a smooth picture comes back close, not exact. */
static void test_jpeg(void)
{
    make_tmpdir();
    char path[512];
    snprintf(path, sizeof path, "%s/frame.jpg", tmpdir);
    enum { JW = 32, JH = 16 };
    float rgb[JW * JH * 3];
    for (int y = 0; y < JH; y++)
        for (int x = 0; x < JW; x++) {
            float *p = rgb + 3 * (y * JW + x);
            p[0] = (float)x / (JW - 1);
            p[1] = (float)y / (JH - 1);
            p[2] = 0.5f;
        }
    orr_image_meta m = test_meta();
    orr_error err;
    orr_error_clear(&err);
    CHECK(orr_write_oiio(path, rgb, JW, JH, 3, 16, &m, &err) == ORR_OK); /* JPEG stores 8 bits */
    float *px = NULL;
    int w = 0, h = 0, n = 0;
    CHECK(orr_read_oiio(path, &px, &w, &h, &n, &err) == ORR_OK);
    CHECK(w == JW && h == JH && n == 3);
    double sum = 0, worst = 0;
    for (int i = 0; px && n == 3 && i < JW * JH * 3; i++) {
        double d = fabs(px[i] - rgb[i]);
        sum += d;
        worst = d > worst ? d : worst;
    }
    CHECK(sum / (JW * JH * 3) < 0.02);
    CHECK(worst < 0.1);
    free(px);
    char buf[1024];
    get_attr(path, "ImageDescription", buf, sizeof buf);
    CHECK_CONTAINS(buf, "scene=future-sky");
    get_attr(path, "format", buf, sizeof buf);
    CHECK(strcmp(buf, "uint8") == 0);
    remove_tmpdir();
}

static void test_unknown_extension(void)
{
    make_tmpdir();
    char path[512];
    float rgb[W * H * 3];
    fill_rgb(rgb);
    orr_error err;
    orr_error_clear(&err);
    snprintf(path, sizeof path, "%s/frame.nosuchformat", tmpdir);
    CHECK(orr_write_oiio(path, rgb, W, H, 3, 8, NULL, &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, path);
    CHECK_CONTAINS(err.msg, "no image format");
    CHECK_CONTAINS(err.msg, "OpenImageIO could not find a format writer");
    /* The dispatcher sends unknown extensions to OpenImageIO as well. */
    orr_error_clear(&err);
    snprintf(path, sizeof path, "%s/noextension", tmpdir);
    CHECK(orr_write_image_rgb(path, rgb, W, H, 8, NULL, &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "noextension");
    CHECK(count_entries() == 0);
    remove_tmpdir();
}

static void test_unwritable_path(void)
{
    make_tmpdir();
    char file[512], path[600];
    snprintf(file, sizeof file, "%s/regular", tmpdir);
    FILE *f = fopen(file, "w");
    fclose(f);
    snprintf(path, sizeof path, "%s/frame.tif", file);
    float rgb[W * H * 3];
    fill_rgb(rgb);
    orr_error err;
    orr_error_clear(&err);
    CHECK(orr_write_oiio(path, rgb, W, H, 3, 16, NULL, &err) == ORR_ERR_IO);
    CHECK_CONTAINS(err.msg, file);
    CHECK_CONTAINS(err.msg, "frame.tif");
    CHECK(count_entries() == 1);
    remove_tmpdir();
}

/* OpenImageIO's HDR writer refuses one channel when it opens the file (after
 * the temporary file exists): the error comes back with its message, the
 * old file stays and no temporary file is left. */
static void test_writer_error_keeps_old_file(void)
{
    make_tmpdir();
    char path[512];
    snprintf(path, sizeof path, "%s/keep.hdr", tmpdir);
    FILE *f = fopen(path, "w");
    fputs("old", f);
    fclose(f);
    float px[W * H] = {0};
    orr_error err;
    orr_error_clear(&err);
    orr_status st = orr_write_oiio(path, px, W, H, 1, 32, NULL, &err);
    CHECK(st == ORR_ERR_IO);
    CHECK_CONTAINS(err.msg, path);
    CHECK_CONTAINS(err.msg, "3-channel");
    CHECK(count_entries() == 1);
    char buf[8] = "";
    f = fopen(path, "r");
    CHECK(f && fgets(buf, sizeof buf, f) && strcmp(buf, "old") == 0);
    if (f)
        fclose(f);
    remove_tmpdir();
}

/* Writers that write no file, or would drop channels or abort, are refused
 * before anything is created. */
static void test_refused_writers(void)
{
    make_tmpdir();
    char path[512];
    float px[W * H * 5] = {0};
    orr_error err;
    orr_error_clear(&err);
    snprintf(path, sizeof path, "%s/frame.term", tmpdir);
    CHECK(orr_write_oiio(path, px, W, H, 3, 8, NULL, &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "writes no file");
    snprintf(path, sizeof path, "%s/frame.null", tmpdir);
    CHECK(orr_write_oiio(path, px, W, H, 3, 8, NULL, &err) == ORR_ERR_USAGE);
    snprintf(path, sizeof path, "%s/frame.jpg", tmpdir);
    CHECK(orr_write_oiio(path, px, W, H, 5, 8, NULL, &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "at most 4 channels");
    snprintf(path, sizeof path, "%s/frame.dpx", tmpdir);
    CHECK(orr_write_oiio(path, px, W, H, 2, 16, NULL, &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "1, 3 or 4 channels");
    CHECK(orr_write_oiio(path, px, W, H, 5, 16, NULL, &err) == ORR_ERR_USAGE);
    CHECK(count_entries() == 0);
    remove_tmpdir();
}

static void test_bad_arguments_and_reads(void)
{
    float rgb[W * H * 3];
    fill_rgb(rgb);
    orr_error err;
    orr_error_clear(&err);
    CHECK(orr_write_oiio("/tmp/x.tif", rgb, W, H, 3, 12, NULL, &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "12");
    CHECK(orr_write_oiio("/tmp/x.tif", rgb, 0, H, 3, 8, NULL, &err) == ORR_ERR_USAGE);
    CHECK(orr_write_oiio("/tmp/x.tif", rgb, W, H, 0, 8, NULL, &err) == ORR_ERR_USAGE);
    CHECK(orr_write_oiio("", rgb, W, H, 3, 8, NULL, &err) == ORR_ERR_USAGE);
    float *px = NULL;
    int w, h, n;
    CHECK(orr_read_oiio("/nonexistent/orrery.tif", &px, &w, &h, &n, &err) == ORR_ERR_IO);
    CHECK_CONTAINS(err.msg, "/nonexistent/orrery.tif");
    CHECK(px == NULL);
    char buf[16];
    CHECK(orr_oiio_get_attribute("/nonexistent/orrery.tif", "Software", buf, sizeof buf, &err) == ORR_ERR_IO);
}

/* The text form and the checks of orr_image_meta. */
static void test_meta_text(void)
{
    char buf[512];
    CHECK(orr_image_meta_text(NULL, buf, sizeof buf) == strlen("software=orrery " ORRERY_VERSION));
    CHECK(strcmp(buf, "software=orrery " ORRERY_VERSION) == 0);
    orr_image_meta m = test_meta();
    m.software = "my-sim 2.0";
    m.has_camera = 1;
    m.cam_pos[0] = 0.1;
    m.cam_pos[1] = -2.5e-20;
    m.cam_pos[2] = 1.0 / 3;
    m.cam_quat[0] = 1;
    m.nextra = 2;
    m.extra_key[0] = "observer";
    m.extra_value[0] = "42";
    m.extra_key[1] = "units.length";
    m.extra_value[1] = "kpc";
    const char *want = "software=my-sim 2.0\nscene=future-sky\nframe=7\ntime=13.75\nprojection=dome\n"
                       "camera.position=0.1 -2.5e-20 0.33333333333333331\ncamera.quaternion=1 0 0 0\n"
                       "observer=42\nunits.length=kpc";
    size_t len = orr_image_meta_text(&m, buf, sizeof buf);
    CHECK(len == strlen(want));
    CHECK(strcmp(buf, want) == 0);
    char small[10];
    CHECK(orr_image_meta_text(&m, small, sizeof small) == strlen(want));
    CHECK(strcmp(small, "software=") == 0);
    CHECK(strtod("0.33333333333333331", NULL) == 1.0 / 3);

    orr_error err;
    orr_error_clear(&err);
    CHECK(orr_image_meta_check(&m, "f.tif", &err) == ORR_OK);
    m.extra_key[1] = "";
    CHECK(orr_image_meta_check(&m, "f.tif", &err) == ORR_ERR_USAGE);
    m.extra_key[1] = "k";
    m.extra_value[1] = "tab\there";
    CHECK(orr_image_meta_check(&m, "f.tif", &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "f.tif");
    m.extra_value[1] = "ok";
    m.nextra = ORR_IMAGE_META_MAX_EXTRA + 1;
    CHECK(orr_image_meta_check(&m, "f.tif", &err) == ORR_ERR_USAGE);
    m.nextra = 0;
    m.frame = 3000000000L;
    CHECK(orr_image_meta_check(&m, "f.tif", &err) == ORR_ERR_USAGE);
}

static void test_format_for_path(void)
{
    CHECK(orr_image_format_for_path("a/b/frame.png") == ORR_IMAGE_PNG);
    CHECK(orr_image_format_for_path("frame.PNG") == ORR_IMAGE_PNG);
    CHECK(orr_image_format_for_path("frame.fits") == ORR_IMAGE_FITS);
    CHECK(orr_image_format_for_path("frame.fit") == ORR_IMAGE_FITS);
    CHECK(orr_image_format_for_path("frame.fts") == ORR_IMAGE_FITS);
    CHECK(orr_image_format_for_path("frame.Exr") == ORR_IMAGE_EXR);
    CHECK(orr_image_format_for_path("frame.tif") == ORR_IMAGE_OIIO);
    CHECK(orr_image_format_for_path("frame.jpg") == ORR_IMAGE_OIIO);
    CHECK(orr_image_format_for_path("dir.png/frame") == ORR_IMAGE_OIIO);
    CHECK(orr_image_format_for_path(".png") == ORR_IMAGE_OIIO);
    CHECK(strcmp(orr_image_format_name(ORR_IMAGE_EXR), "OpenEXR") == 0);
}

/* orr_write_image_rgb in each format, read back through OpenImageIO. */
static void test_dispatch_rgb(void)
{
    make_tmpdir();
    float rgb[W * H * 3];
    fill_rgb(rgb);
    rgb[5] = 0.5f;
    orr_image_meta m = test_meta();
    orr_error err;
    orr_error_clear(&err);
    char path[512], buf[1024];

    /* PNG through libpng, with the description as a tEXt chunk. */
    snprintf(path, sizeof path, "%s/frame.png", tmpdir);
    CHECK(orr_write_image_rgb(path, rgb, W, H, 16, &m, &err) == ORR_OK);
    float *px = NULL;
    int w = 0, h = 0, n = 0;
    CHECK(orr_read_oiio(path, &px, &w, &h, &n, &err) == ORR_OK);
    CHECK(n == 3 && px && fabsf(px[6] - rgb[6]) <= 0.5f / 65535 + 1e-7f);
    free(px);
    get_attr(path, "ImageDescription", buf, sizeof buf);
    CHECK_CONTAINS(buf, "frame=7");
    get_attr(path, "Software", buf, sizeof buf);
    CHECK(strcmp(buf, "orrery " ORRERY_VERSION) == 0);

    /* OpenEXR holds linear light: sRGB 0.5 comes back as 0.214. */
    snprintf(path, sizeof path, "%s/frame.exr", tmpdir);
    CHECK(orr_write_image_rgb(path, rgb, W, H, 16, &m, &err) == ORR_OK);
    px = NULL;
    CHECK(orr_read_oiio(path, &px, &w, &h, &n, &err) == ORR_OK);
    CHECK(n == 3 && px);
    if (px && n == 3) {
        CHECK_NEAR(px[5], 0.21404114, 0.21404114 * 0x1p-11);
        CHECK(px[0] == 0 && px[1] == 1);
    }
    free(px);
    get_attr(path, "format", buf, sizeof buf);
    CHECK(strcmp(buf, "half") == 0);

    /* 16-bit TIFF through OpenImageIO. */
    snprintf(path, sizeof path, "%s/frame.tif", tmpdir);
    CHECK(orr_write_image_rgb(path, rgb, W, H, 16, &m, &err) == ORR_OK);
    get_attr(path, "DocumentName", buf, sizeof buf);
    CHECK(strcmp(buf, "future-sky") == 0);

    /* FITS: three planes, values unchanged. */
    snprintf(path, sizeof path, "%s/frame.fits", tmpdir);
    CHECK(orr_write_image_rgb(path, rgb, W, H, 16, &m, &err) == ORR_OK);
    CHECK(count_entries() == 4);

    /* Linear planes cannot go to PNG. */
    orr_plane p;
    CHECK(orr_plane_alloc(&p, W, H, "mass", "", &err) == ORR_OK);
    snprintf(path, sizeof path, "%s/planes.png", tmpdir);
    CHECK(orr_write_image_planes(path, &p, 1, &m, &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "PNG");
    orr_plane_free(&p);
    CHECK(count_entries() == 4);
    remove_tmpdir();
}

int main(void)
{
    RUN(test_tiff16_round_trip);
    RUN(test_tiff_float_named_planes);
    RUN(test_jpeg);
    RUN(test_unknown_extension);
    RUN(test_unwritable_path);
    RUN(test_writer_error_keeps_old_file);
    RUN(test_refused_writers);
    RUN(test_bad_arguments_and_reads);
    RUN(test_meta_text);
    RUN(test_format_for_path);
    RUN(test_dispatch_rgb);
    return check_summary();
}
