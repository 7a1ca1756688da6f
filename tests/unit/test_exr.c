/* OpenEXR output (src/encode/exr.c), read back through OpenImageIO: values
 * (float exactly, half within half precision), channel names, header
 * attributes, and failures that leave no file behind. */
#include <dirent.h>
#include <math.h>
#include <stdlib.h>
#include <sys/stat.h>
#include <unistd.h>

#include "tmpdir.h"
#include "check.h"
#include "encode/exr.h"
#include "encode/oiio.h"

enum { W = 5, H = 19 }; /* more rows than one 16-line ZIP block */

/* A plane of values spanning many magnitudes and both signs. */
static void fill_plane(orr_plane *p, const char *name, int seed)
{
    orr_error err;
    if (orr_plane_alloc(p, W, H, name, "", &err) != ORR_OK) {
        fprintf(stderr, "%s\n", err.msg);
        exit(1);
    }
    for (int i = 0; i < W * H; i++) {
        double v = sin(0.37 * i + seed) * pow(10.0, (i + seed) % 9 - 4);
        p->data[i] = (float)v;
    }
}

/* Half has an 11-bit significand: rounding to nearest is within 2^-11 of
 * the value, or half the smallest subnormal (2^-25) near zero. */
static int half_close(float got, float want)
{
    return fabsf(got - want) <= fabsf(want) * 0x1p-11f + 0x1p-25f;
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
    m.scene = "milky-way-m31";
    m.projection = "hammer-aitoff";
    m.has_frame = 1;
    m.frame = 1234;
    m.has_time = 1;
    m.time = 0.1;
    m.has_camera = 1;
    m.cam_pos[0] = 1;
    m.cam_pos[1] = 2;
    m.cam_pos[2] = 3;
    m.cam_quat[0] = 1; /* identity: camera axes are the world axes */
    m.nextra = 1;
    m.extra_key[0] = "observer";
    m.extra_value[0] = "sun (id 42)";
    return m;
}

static void test_float_rgb_round_trip(void)
{
    make_tmpdir();
    char path[512];
    snprintf(path, sizeof path, "%s/rgb.exr", tmpdir);
    orr_plane r, g, b;
    fill_plane(&r, "R", 0);
    fill_plane(&g, "G", 1);
    fill_plane(&b, "B", 2);
    b.data[7] = 1e30f; /* far beyond half's range: float keeps it */
    b.data[8] = -0.0f;
    const orr_plane *ch[3] = {&r, &g, &b};
    orr_image_meta m = test_meta();
    orr_error err;
    orr_error_clear(&err);
    CHECK(orr_write_exr(path, ch, 3, ORR_EXR_FLOAT, &m, &err) == ORR_OK);
    CHECK(count_entries() == 1);

    float *px = NULL;
    int w = 0, h = 0, n = 0;
    CHECK(orr_read_oiio(path, &px, &w, &h, &n, &err) == ORR_OK);
    CHECK(w == W && h == H && n == 3);
    int bad = 0;
    for (int i = 0; px && w == W && h == H && n == 3 && i < W * H; i++)
        bad += px[3 * i] != r.data[i] || px[3 * i + 1] != g.data[i] || px[3 * i + 2] != b.data[i];
    CHECK(bad == 0);
    free(px);

    char buf[1024];
    get_attr(path, "compression", buf, sizeof buf);
    CHECK(strcmp(buf, "zip") == 0);
    get_attr(path, "format", buf, sizeof buf);
    CHECK(strcmp(buf, "float") == 0);
    orr_plane_free(&r);
    orr_plane_free(&g);
    orr_plane_free(&b);
    remove_tmpdir();
}

static void test_named_half_round_trip(void)
{
    make_tmpdir();
    char path[512];
    snprintf(path, sizeof path, "%s/named.exr", tmpdir);
    orr_plane mass, x, y, z;
    fill_plane(&mass, "mass", 3);
    fill_plane(&x, "X", 4);
    fill_plane(&y, "Y", 5);
    fill_plane(&z, "Z", 6);
    mass.data[0] = 70000.0f; /* beyond half's largest, 65504 */
    mass.data[1] = 65504.0f;
    const orr_plane *ch[4] = {&mass, &x, &y, &z};
    orr_error err;
    orr_error_clear(&err);
    CHECK(orr_write_exr(path, ch, 4, ORR_EXR_HALF, NULL, &err) == ORR_OK);

    orr_plane *planes = NULL;
    int n = 0;
    CHECK(orr_read_oiio_planes(path, &planes, &n, &err) == ORR_OK);
    CHECK(n == 4);
    int found = 0, bad = 0;
    for (int k = 0; k < n; k++) {
        const orr_plane *want = NULL;
        for (int c = 0; c < 4; c++)
            if (!strcmp(planes[k].name, ch[c]->name))
                want = ch[c];
        if (!want)
            continue;
        found++;
        CHECK(planes[k].width == W && planes[k].height == H);
        for (int i = (want == &mass ? 1 : 0); i < W * H; i++)
            bad += !half_close(planes[k].data[i], want->data[i]);
        if (want == &mass) {
            CHECK(isinf(planes[k].data[0]) && planes[k].data[0] > 0);
            CHECK(planes[k].data[1] == 65504.0f);
        }
    }
    CHECK(found == 4);
    CHECK(bad == 0);
    for (int k = 0; k < n; k++)
        orr_plane_free(&planes[k]);
    free(planes);

    char buf[256];
    get_attr(path, "format", buf, sizeof buf);
    CHECK(strcmp(buf, "half") == 0);
    orr_plane_free(&mass);
    orr_plane_free(&x);
    orr_plane_free(&y);
    orr_plane_free(&z);
    remove_tmpdir();
}

/* Parses n numbers separated by ", " (OpenImageIO's array text). */
static int parse_numbers(const char *s, double *v, int n)
{
    for (int i = 0; i < n; i++) {
        char *end;
        v[i] = strtod(s, &end);
        if (end == s)
            return 0;
        s = end;
        while (*s == ',' || *s == ' ')
            s++;
    }
    return *s == '\0';
}

static void test_metadata_attributes(void)
{
    make_tmpdir();
    char path[512];
    snprintf(path, sizeof path, "%s/meta.exr", tmpdir);
    orr_plane r;
    fill_plane(&r, "R", 0);
    const orr_plane *ch[1] = {&r};
    orr_image_meta m = test_meta();
    orr_error err;
    orr_error_clear(&err);
    CHECK(orr_write_exr(path, ch, 1, ORR_EXR_HALF, &m, &err) == ORR_OK);

    char buf[1024];
    get_attr(path, "ImageDescription", buf, sizeof buf); /* the "comments" attribute */
    CHECK_CONTAINS(buf, "software=orrery " ORRERY_VERSION "\n");
    CHECK_CONTAINS(buf, "scene=milky-way-m31\n");
    CHECK_CONTAINS(buf, "frame=1234\n");
    CHECK_CONTAINS(buf, "time=0.1\n");
    CHECK_CONTAINS(buf, "projection=hammer-aitoff\n");
    CHECK_CONTAINS(buf, "camera.position=1 2 3\n");
    CHECK_CONTAINS(buf, "camera.quaternion=1 0 0 0\n");
    CHECK_CONTAINS(buf, "observer=sun (id 42)");
    get_attr(path, "software", buf, sizeof buf);
    CHECK(strcmp(buf, "orrery " ORRERY_VERSION) == 0);
    get_attr(path, "orrery:scene", buf, sizeof buf);
    CHECK(strcmp(buf, "milky-way-m31") == 0);
    get_attr(path, "orrery:projection", buf, sizeof buf);
    CHECK(strcmp(buf, "hammer-aitoff") == 0);
    get_attr(path, "orrery:frame", buf, sizeof buf);
    CHECK(strcmp(buf, "1234") == 0);
    get_attr(path, "orrery:time", buf, sizeof buf);
    CHECK(strtod(buf, NULL) == 0.1);
    get_attr(path, "orrery:observer", buf, sizeof buf);
    CHECK(strcmp(buf, "sun (id 42)") == 0);
    double v[16];
    get_attr(path, "orrery:cameraPosition", buf, sizeof buf);
    CHECK(parse_numbers(buf, v, 3) && v[0] == 1 && v[1] == 2 && v[2] == 3);
    get_attr(path, "orrery:cameraQuatW", buf, sizeof buf);
    CHECK(strtod(buf, NULL) == 1);
    get_attr(path, "orrery:cameraQuatZ", buf, sizeof buf);
    CHECK(strtod(buf, NULL) == 0);

    /* worldToCamera, row vectors: camera x = world x, camera y (up) = -world
     * y (orrery's image y points down), camera z = world z, origin at the
     * camera position (1, 2, 3). */
    get_attr(path, "worldtocamera", buf, sizeof buf);
    static const double want[16] = {1, 0, 0, 0, 0, -1, 0, 0, 0, 0, 1, 0, -1, 2, -3, 1};
    int ok = parse_numbers(buf, v, 16);
    CHECK(ok);
    for (int i = 0; ok && i < 16; i++)
        CHECK_NEAR(v[i], want[i], 1e-6);
    orr_plane_free(&r);
    remove_tmpdir();
}

/* A turned camera: worldToCamera must map the camera's view direction
 * (orrery's camera +z) to OpenEXR's +z and its image-down to -y. */
static void test_world_to_camera_rotated(void)
{
    make_tmpdir();
    char path[512];
    snprintf(path, sizeof path, "%s/turned.exr", tmpdir);
    orr_plane r;
    fill_plane(&r, "R", 0);
    const orr_plane *ch[1] = {&r};
    orr_image_meta m = {0};
    m.has_camera = 1;
    /* 90 degrees about world z: camera x -> world y, camera y -> world -x. */
    m.cam_quat[0] = cos(atan(1.0));
    m.cam_quat[3] = sin(atan(1.0));
    m.cam_pos[0] = 5;
    orr_error err;
    orr_error_clear(&err);
    CHECK(orr_write_exr(path, ch, 1, ORR_EXR_FLOAT, &m, &err) == ORR_OK);
    char buf[1024];
    get_attr(path, "worldtocamera", buf, sizeof buf);
    double M[16];
    CHECK(parse_numbers(buf, M, 16));
    /* p_cam = p * M for a world point one unit along world y from the
     * camera: that is camera +x (right), so EXR camera (1, 0, 0). */
    double p[3] = {5, 1, 0}, q[3];
    for (int j = 0; j < 3; j++)
        q[j] = p[0] * M[j] + p[1] * M[4 + j] + p[2] * M[8 + j] + M[12 + j];
    CHECK_NEAR(q[0], 1, 1e-6);
    CHECK_NEAR(q[1], 0, 1e-6);
    CHECK_NEAR(q[2], 0, 1e-6);
    /* world -x from the camera is orrery camera +y (image down): EXR y = -1. */
    double p2[3] = {4, 0, 0};
    for (int j = 0; j < 3; j++)
        q[j] = p2[0] * M[j] + p2[1] * M[4 + j] + p2[2] * M[8 + j] + M[12 + j];
    CHECK_NEAR(q[0], 0, 1e-6);
    CHECK_NEAR(q[1], -1, 1e-6);
    CHECK_NEAR(q[2], 0, 1e-6);
    orr_plane_free(&r);
    remove_tmpdir();
}

/* Channel names past OpenEXR's 31-character short-name limit turn on the
 * long-name flag; other compressions write readable files too. */
static void test_long_names_and_compressions(void)
{
    make_tmpdir();
    char path[512];
    static const orr_exr_compression comps[] = {ORR_EXR_ZIPS, ORR_EXR_PIZ, ORR_EXR_RLE, ORR_EXR_NONE};
    static const char *const comp_names[] = {"zips", "piz", "rle", "none"};
    orr_plane a;
    fill_plane(&a, "luminosity_of_the_young_population_in_V", 7);
    const orr_plane *ch[1] = {&a};
    orr_image_meta m = {0};
    m.nextra = 1;
    m.extra_key[0] = "a_rather_long_key_for_an_extra_pair";
    m.extra_value[0] = "v";
    for (int k = 0; k < 4; k++) {
        snprintf(path, sizeof path, "%s/c%d.exr", tmpdir, k);
        orr_error err;
        orr_error_clear(&err);
        CHECK(orr_write_exr_compressed(path, ch, 1, ORR_EXR_FLOAT, comps[k], &m, &err) == ORR_OK);
        char buf[256];
        get_attr(path, "compression", buf, sizeof buf);
        CHECK(strcmp(buf, comp_names[k]) == 0);
        get_attr(path, "orrery:a_rather_long_key_for_an_extra_pair", buf, sizeof buf);
        CHECK(strcmp(buf, "v") == 0);
        orr_plane *planes = NULL;
        int n = 0;
        CHECK(orr_read_oiio_planes(path, &planes, &n, &err) == ORR_OK);
        CHECK(n == 1 && planes && !strcmp(planes[0].name, a.name));
        int bad = 0;
        for (int i = 0; n == 1 && i < W * H; i++)
            bad += planes[0].data[i] != a.data[i];
        CHECK(bad == 0);
        for (int i = 0; i < n; i++)
            orr_plane_free(&planes[i]);
        free(planes);
    }
    orr_plane_free(&a);
    remove_tmpdir();
}

static void test_bad_arguments(void)
{
    make_tmpdir();
    char path[512];
    snprintf(path, sizeof path, "%s/bad.exr", tmpdir);
    orr_plane a, b, small;
    fill_plane(&a, "R", 0);
    fill_plane(&b, "R", 1);
    orr_error err;
    orr_plane_alloc(&small, 2, 2, "G", "", &err);
    orr_error_clear(&err);

    const orr_plane *dup[2] = {&a, &b};
    CHECK(orr_write_exr(path, dup, 2, ORR_EXR_HALF, NULL, &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "two channels are named R");
    CHECK_CONTAINS(err.msg, path);
    const orr_plane *sizes[2] = {&a, &small};
    CHECK(orr_write_exr(path, sizes, 2, ORR_EXR_HALF, NULL, &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "2 x 2");
    b.name[0] = '\0';
    const orr_plane *unnamed[1] = {&b};
    CHECK(orr_write_exr(path, unnamed, 1, ORR_EXR_HALF, NULL, &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "no name");
    const orr_plane *one[1] = {&a};
    CHECK(orr_write_exr(path, one, 0, ORR_EXR_HALF, NULL, &err) == ORR_ERR_USAGE);
    CHECK(orr_write_exr(path, one, 1, (orr_exr_pixel)7, NULL, &err) == ORR_ERR_USAGE);
    CHECK(orr_write_exr("", one, 1, ORR_EXR_HALF, NULL, &err) == ORR_ERR_USAGE);

    orr_image_meta m = {0};
    m.scene = "two\nlines";
    CHECK(orr_write_exr(path, one, 1, ORR_EXR_HALF, &m, &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "scene");
    m.scene = NULL;
    m.nextra = 1;
    m.extra_key[0] = "has space";
    m.extra_value[0] = "x";
    CHECK(orr_write_exr(path, one, 1, ORR_EXR_HALF, &m, &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "has space");
    CHECK(count_entries() == 0);
    orr_plane_free(&a);
    orr_plane_free(&b);
    orr_plane_free(&small);
    remove_tmpdir();
}

/* A folder that cannot exist (its parent is a regular file): the error
 * names it and nothing is created. */
static void test_unwritable_path(void)
{
    make_tmpdir();
    char file[512], path[600];
    snprintf(file, sizeof file, "%s/regular", tmpdir);
    FILE *f = fopen(file, "w");
    fclose(f);
    snprintf(path, sizeof path, "%s/frame.exr", file);
    orr_plane a;
    fill_plane(&a, "R", 0);
    const orr_plane *one[1] = {&a};
    orr_error err;
    orr_error_clear(&err);
    CHECK(orr_write_exr(path, one, 1, ORR_EXR_HALF, NULL, &err) == ORR_ERR_IO);
    CHECK_CONTAINS(err.msg, file);
    CHECK_CONTAINS(err.msg, "frame.exr");
    CHECK(count_entries() == 1);
    orr_plane_free(&a);
    remove_tmpdir();
}

/* A new file replaces an old one of the same name in one step, and no
 * temporary file stays behind. */
static void test_replaces_old_file(void)
{
    make_tmpdir();
    char path[512];
    snprintf(path, sizeof path, "%s/frame.exr", tmpdir);
    FILE *f = fopen(path, "w");
    fputs("old", f);
    fclose(f);
    orr_plane a;
    fill_plane(&a, "Y", 0);
    const orr_plane *one[1] = {&a};
    orr_error err;
    orr_error_clear(&err);
    CHECK(orr_write_exr(path, one, 1, ORR_EXR_FLOAT, NULL, &err) == ORR_OK);
    CHECK(count_entries() == 1);
    struct stat st;
    CHECK(stat(path, &st) == 0 && st.st_size > 100);
    float *px = NULL;
    int w, h, n;
    CHECK(orr_read_oiio(path, &px, &w, &h, &n, &err) == ORR_OK);
    CHECK(px && n == 1 && px[W * H - 1] == a.data[W * H - 1]);
    free(px);
    orr_plane_free(&a);
    remove_tmpdir();
}

int main(void)
{
    RUN(test_float_rgb_round_trip);
    RUN(test_named_half_round_trip);
    RUN(test_metadata_attributes);
    RUN(test_world_to_camera_rotated);
    RUN(test_long_names_and_compressions);
    RUN(test_bad_arguments);
    RUN(test_unwritable_path);
    RUN(test_replaces_old_file);
    return check_summary();
}
