/* The ffmpeg command of `orrery video`, word for word: the frames read from
 * standard input, the options each codec needs (docs/animation.md, "Making
 * a video"), the padding of odd sizes, and the output name passed literally. tests/cli/test_video.sh runs
 * ffmpeg with them and checks the videos it makes. */
#include <stdlib.h>

#include "check.h"
/* The command builder is part of the CLI, not of the library the tests link
 * against, so it is compiled in here. */
#include "cli/video_command.c"

/* The word after option `opt` (the last occurrence), or NULL. */
static const char *value_of(const video_command *cmd, const char *opt)
{
    const char *v = NULL;
    for (int i = 0; i + 1 < cmd->argc; i++)
        if (strcmp(cmd->argv[i], opt) == 0)
            v = cmd->argv[i + 1];
    return v;
}

static int has_word(const video_command *cmd, const char *word)
{
    for (int i = 0; i < cmd->argc; i++)
        if (strcmp(cmd->argv[i], word) == 0)
            return 1;
    return 0;
}

static video_settings settings(video_codec codec)
{
    video_settings s = {.ffmpeg = "/usr/bin/ffmpeg", .fps = "24", .codec = codec,
                        .crf = video_codec_default_crf(codec), .output = "out dir/.clip.mp4.tmp-AbC123"};
    return s;
}

static void test_h264_odd_size_word_for_word(void)
{
    video_settings s = settings(VIDEO_H264);
    s.pad_width = 66;
    s.pad_height = 50;
    video_command cmd;
    CHECK(video_command_build(&cmd, &s));
    static const char filter[] = "pad=66:50:0:0:black,scale=out_color_matrix=bt709:out_range=tv,format=yuv420p,"
                                 "setparams=range=tv:color_primaries=bt709:color_trc=bt709:colorspace=bt709";
    static const char *const expected[] = {
        "/usr/bin/ffmpeg", "-hide_banner", "-loglevel", "error", "-xerror", "-y",
        "-f", "image2pipe", "-framerate", "24", "-c:v", "png", "-i", "pipe:0",
        "-vf", filter,
        "-c:v", "libx264", "-crf", "18", "-pix_fmt", "yuv420p", "-movflags", "+faststart",
        "-f", "mp4", "file:out dir/.clip.mp4.tmp-AbC123"};
    int n = (int)(sizeof expected / sizeof expected[0]);
    CHECK(cmd.argc == n);
    for (int i = 0; i < n && i < cmd.argc; i++)
        if (strcmp(cmd.argv[i], expected[i]) != 0) {
            fprintf(stderr, "word %d: got '%s', expected '%s'\n", i, cmd.argv[i], expected[i]);
            CHECK(0);
        }
    CHECK(cmd.argv[cmd.argc] == NULL); /* posix_spawn needs the terminator */
}

static void test_even_size_is_not_padded(void)
{
    video_settings s = settings(VIDEO_H264);
    s.crf = 0; /* lossless is a valid CRF */
    video_command cmd;
    CHECK(video_command_build(&cmd, &s));
    CHECK(strncmp(value_of(&cmd, "-vf"), "scale=out_color_matrix=bt709", 28) == 0);
    CHECK(strcmp(value_of(&cmd, "-crf"), "0") == 0);
}

static void test_h265_is_tagged_hvc1_and_quiet(void)
{
    video_settings s = settings(VIDEO_H265);
    video_command cmd;
    CHECK(video_command_build(&cmd, &s));
    CHECK(strcmp(value_of(&cmd, "-c:v"), "libx265") == 0);
    CHECK(strcmp(value_of(&cmd, "-tag:v"), "hvc1") == 0);
    CHECK(strcmp(value_of(&cmd, "-crf"), "23") == 0);
    CHECK(strcmp(value_of(&cmd, "-x265-params"), "log-level=error") == 0);
    CHECK(strcmp(value_of(&cmd, "-pix_fmt"), "yuv420p") == 0);
    CHECK(strcmp(value_of(&cmd, "-f"), "mp4") == 0);
    CHECK(has_word(&cmd, "+faststart"));
}

static void test_prores_master(void)
{
    video_settings s = settings(VIDEO_PRORES);
    s.output = "masters/clip.mov";
    video_command cmd;
    CHECK(video_command_build(&cmd, &s));
    CHECK(strcmp(value_of(&cmd, "-c:v"), "prores_ks") == 0);
    CHECK(strcmp(value_of(&cmd, "-profile:v"), "3") == 0);
    CHECK(strcmp(value_of(&cmd, "-pix_fmt"), "yuv422p10le") == 0);
    CHECK_CONTAINS(value_of(&cmd, "-vf"), "format=yuv422p10le");
    CHECK(strcmp(value_of(&cmd, "-f"), "mov") == 0);
    CHECK(!has_word(&cmd, "-crf"));
    CHECK(!has_word(&cmd, "-movflags"));
    CHECK(strcmp(cmd.argv[cmd.argc - 1], "file:masters/clip.mov") == 0);
}

static void test_png_keeps_the_pixels(void)
{
    video_settings s = settings(VIDEO_PNG);
    video_command cmd;
    CHECK(video_command_build(&cmd, &s));
    CHECK(strcmp(value_of(&cmd, "-c:v"), "png") == 0);
    CHECK(strcmp(value_of(&cmd, "-f"), "mov") == 0);
    CHECK(!has_word(&cmd, "-vf"));      /* no conversion to YUV */
    CHECK(!has_word(&cmd, "-pix_fmt")); /* the frames' own RGB */
    CHECK(!has_word(&cmd, "-crf"));
}

static void test_codec_table(void)
{
    video_codec c;
    CHECK(video_codec_parse("h264", &c) && c == VIDEO_H264);
    CHECK(video_codec_parse("h265", &c) && c == VIDEO_H265);
    CHECK(video_codec_parse("prores", &c) && c == VIDEO_PRORES);
    CHECK(video_codec_parse("png", &c) && c == VIDEO_PNG);
    CHECK(!video_codec_parse("H264", &c));
    CHECK(!video_codec_parse("vp9", &c));
    CHECK(!video_codec_parse("", &c));
    CHECK(strcmp(video_codec_extension(VIDEO_H264), "mp4") == 0);
    CHECK(strcmp(video_codec_extension(VIDEO_H265), "mp4") == 0);
    CHECK(strcmp(video_codec_extension(VIDEO_PRORES), "mov") == 0);
    CHECK(strcmp(video_codec_extension(VIDEO_PNG), "mov") == 0);
    CHECK(video_codec_has_crf(VIDEO_H264) && video_codec_has_crf(VIDEO_H265));
    CHECK(!video_codec_has_crf(VIDEO_PRORES) && !video_codec_has_crf(VIDEO_PNG));
    CHECK(video_codec_needs_even_width(VIDEO_H264) && video_codec_needs_even_height(VIDEO_H264));
    CHECK(video_codec_needs_even_width(VIDEO_H265) && video_codec_needs_even_height(VIDEO_H265));
    CHECK(!video_codec_needs_even_width(VIDEO_PNG) && !video_codec_needs_even_height(VIDEO_PNG));
}

static void test_names_are_literal(void)
{
    /* A name starting with '-' or holding ':' reaches ffmpeg as a file. */
    video_settings s = settings(VIDEO_H264);
    s.output = "-x:100%.mp4";
    video_command cmd;
    CHECK(video_command_build(&cmd, &s));
    CHECK(strcmp(cmd.argv[cmd.argc - 1], "file:-x:100%.mp4") == 0);
    CHECK(strcmp(value_of(&cmd, "-i"), "pipe:0") == 0);
}

static void test_too_long_is_refused(void)
{
    size_t n = 3 * 4096;
    char *huge = malloc(n + 1);
    memset(huge, 'a', n);
    huge[n] = '\0';
    video_settings s = settings(VIDEO_H264);
    video_command cmd;
    s.output = huge;
    CHECK(!video_command_build(&cmd, &s));
    free(huge);
}

/* The levels of H.264 (Table A-1) and H.265 (Table A.8) the frames need:
 * frame size, rate, and the limit on each side of thin frames. */
static void test_levels(void)
{
    CHECK(video_level(VIDEO_H264, 64, 48, 30) == 10);
    CHECK(video_level(VIDEO_H264, 1280, 720, 30) == 31);
    CHECK(video_level(VIDEO_H264, 1920, 1080, 30) == 40);
    CHECK(video_level(VIDEO_H264, 1920, 1080, 60) == 42);
    CHECK(video_level(VIDEO_H264, 3840, 2160, 30) == 51);
    CHECK(video_level(VIDEO_H264, 4096, 2304, 30) == 52); /* 36864 macroblocks, 1.1e6 a second */
    CHECK(video_level(VIDEO_H264, 3072, 3072, 30) == 52); /* the largest square dome within 5.2 */
    CHECK(video_level(VIDEO_H264, 3073, 3073, 30) == 60); /* 193 x 193 macroblocks */
    CHECK(video_level(VIDEO_H264, 3072, 3072, 60) == 60); /* the rate too */
    CHECK(video_level(VIDEO_H264, 3600, 3600, 30) == 60); /* issue 19: Future Sky's dome master */
    CHECK(video_level(VIDEO_H264, 8192, 4320, 30) == 60);
    CHECK(video_level(VIDEO_H264, 8192, 4320, 60) == 61);
    CHECK(video_level(VIDEO_H264, 8688, 16, 30) == 51);   /* 543 macroblocks wide: sqrt(8 * 36864) */
    CHECK(video_level(VIDEO_H264, 8704, 16, 30) == 60);   /* 544: too wide for 5.2 */
    CHECK(video_level(VIDEO_H264, 16384, 16384, 30) == -1);
    CHECK(video_level(VIDEO_H265, 1920, 1080, 30) == 40);
    CHECK(video_level(VIDEO_H265, 3840, 2160, 30) == 50);
    CHECK(video_level(VIDEO_H265, 2984, 2984, 30) == 50);
    CHECK(video_level(VIDEO_H265, 2986, 2986, 30) == 60);
    CHECK(video_level(VIDEO_H265, 3600, 3600, 30) == 60);
    CHECK(video_level(VIDEO_PRORES, 3600, 3600, 30) == 0);
    CHECK(video_level(VIDEO_PNG, 8192, 8192, 30) == 0);
}

int main(void)
{
    RUN(test_h264_odd_size_word_for_word);
    RUN(test_even_size_is_not_padded);
    RUN(test_h265_is_tagged_hvc1_and_quiet);
    RUN(test_prores_master);
    RUN(test_png_keeps_the_pixels);
    RUN(test_codec_table);
    RUN(test_names_are_literal);
    RUN(test_too_long_is_refused);
    RUN(test_levels);
    return check_summary();
}
