/* The ffmpeg command line of `orrery video` (see video_command.h). */
#include "cli/video_command.h"

#include <stdio.h>
#include <string.h>

typedef struct codec_info {
    const char *name;      /* as --codec takes it */
    const char *encoder;   /* ffmpeg's encoder */
    const char *extension; /* of the container */
    const char *muxer;     /* ffmpeg's -f */
    const char *pix_fmt;   /* NULL: keep the frames' own (RGB) pixels */
    int default_crf;       /* 0: no --crf */
    int even_width, even_height;
} codec_info;

/* Chroma subsampling: 4:2:0 halves both directions, so libx264 and libx265
 * refuse odd sizes; prores_ks accepts any size (checked with ffmpeg 5.1).
 * The x265 default CRF (28) looks about like x264's default (23), so
 * libx265 gets 23 to match x264's 18, the usual "visually lossless". */
static const codec_info CODECS[] = {
    [VIDEO_H264] = {"h264", "libx264", "mp4", "mp4", "yuv420p", 18, 1, 1},
    [VIDEO_H265] = {"h265", "libx265", "mp4", "mp4", "yuv420p", 23, 1, 1},
    [VIDEO_PRORES] = {"prores", "prores_ks", "mov", "mov", "yuv422p10le", 0, 0, 0},
    [VIDEO_PNG] = {"png", "png", "mov", "mov", NULL, 0, 0, 0},
};

int video_codec_parse(const char *name, video_codec *out)
{
    for (int c = 0; c < (int)(sizeof CODECS / sizeof CODECS[0]); c++)
        if (strcmp(name, CODECS[c].name) == 0) {
            *out = (video_codec)c;
            return 1;
        }
    return 0;
}

const char *video_codec_name(video_codec codec) { return CODECS[codec].name; }
const char *video_codec_extension(video_codec codec) { return CODECS[codec].extension; }
int video_codec_has_crf(video_codec codec) { return CODECS[codec].default_crf > 0; }
int video_codec_default_crf(video_codec codec) { return CODECS[codec].default_crf; }
int video_codec_needs_even_width(video_codec codec) { return CODECS[codec].even_width; }
int video_codec_needs_even_height(video_codec codec) { return CODECS[codec].even_height; }

/* One level of a codec's standard: its number times ten, the most a frame
 * may hold (H.264: 16x16 macroblocks; H.265: luma pixels) and the most a
 * second may. */
typedef struct level_limit {
    int level;
    double max_frame, max_rate;
} level_limit;

/* ITU-T H.264 (08/2021) Table A-1: MaxFS and MaxMBPS (level 1b left out). */
static const level_limit H264_LEVELS[] = {
    {10, 99, 1485},       {11, 396, 3000},      {12, 396, 6000},       {13, 396, 11880},
    {20, 396, 11880},     {21, 792, 19800},     {22, 1620, 20250},     {30, 1620, 40500},
    {31, 3600, 108000},   {32, 5120, 216000},   {40, 8192, 245760},    {41, 8192, 245760},
    {42, 8704, 522240},   {50, 22080, 589824},  {51, 36864, 983040},   {52, 36864, 2073600},
    {60, 139264, 4177920}, {61, 139264, 8355840}, {62, 139264, 16711680},
};

/* ITU-T H.265 (08/2021) Table A.8: MaxLumaPs and MaxLumaSr. */
static const level_limit H265_LEVELS[] = {
    {10, 36864, 552960},       {20, 122880, 3686400},      {21, 245760, 7372800},
    {30, 552960, 16588800},    {31, 983040, 33177600},     {40, 2228224, 66846720},
    {41, 2228224, 133693440},  {50, 8912896, 267386880},   {51, 8912896, 534773760},
    {52, 8912896, 1069547520}, {60, 35651584, 1069547520}, {61, 35651584, 2139095040},
    {62, 35651584, 4278190080.0},
};

/* The first level of the table that holds a frame of `units` (a sides of
 * wide x high units), `units * fps` a second; each side may be at most
 * sqrt(8 * max_frame) units (both standards' limit on thin frames). */
static int first_level(const level_limit *t, int n, double wide, double high, double fps)
{
    for (int i = 0; i < n; i++)
        if (wide * high <= t[i].max_frame && wide * high * fps <= t[i].max_rate &&
            wide * wide <= 8 * t[i].max_frame && high * high <= 8 * t[i].max_frame)
            return t[i].level;
    return -1;
}

int video_level(video_codec codec, int width, int height, double fps)
{
    if (codec == VIDEO_H264) /* in macroblocks, 16x16 pixels, rounded up */
        return first_level(H264_LEVELS, (int)(sizeof H264_LEVELS / sizeof H264_LEVELS[0]), (width + 15) / 16,
                           (height + 15) / 16, fps);
    if (codec == VIDEO_H265) /* in luma pixels */
        return first_level(H265_LEVELS, (int)(sizeof H265_LEVELS / sizeof H265_LEVELS[0]), width, height, fps);
    return 0;
}

static int add(video_command *cmd, const char *word)
{
    if (cmd->argc >= VIDEO_MAX_ARGS - 1)
        return 0;
    cmd->argv[cmd->argc++] = word;
    cmd->argv[cmd->argc] = NULL;
    return 1;
}

/* The filter chain of the YUV codecs: pad to the even size, convert RGB to
 * YUV with the BT.709 matrix, and tag the frames so. ffmpeg's default for
 * RGB input is BT.601, which players decode as 709 for HD, shifting the
 * hues of the star colours; and some encoders (prores_ks) take the tags
 * from the frames only, not from -colorspace. */
static int yuv_filter(video_command *cmd, const video_settings *s, const char *pix_fmt)
{
    char pad[64] = "";
    if (s->pad_width > 0 && s->pad_height > 0)
        snprintf(pad, sizeof pad, "pad=%d:%d:0:0:black,", s->pad_width, s->pad_height);
    int n = snprintf(cmd->filter, sizeof cmd->filter,
                     "%sscale=out_color_matrix=bt709:out_range=tv,format=%s,"
                     "setparams=range=tv:color_primaries=bt709:color_trc=bt709:colorspace=bt709",
                     pad, pix_fmt);
    return n > 0 && n < (int)sizeof cmd->filter;
}

/* "file:" + name into buf. The prefix makes ffmpeg take the name
 * literally: a name with ':' is not a protocol, one starting with '-' is
 * not an option. */
static int file_url(char *buf, size_t size, const char *name)
{
    int n = snprintf(buf, size, "file:%s", name);
    return n > 0 && (size_t)n < size;
}

int video_command_build(video_command *cmd, const video_settings *s)
{
    const codec_info *c = &CODECS[s->codec];
    memset(cmd, 0, sizeof *cmd);
    snprintf(cmd->crf, sizeof cmd->crf, "%d", s->crf);
    if (!file_url(cmd->output, sizeof cmd->output, s->output))
        return 0;
    /* The frames come as PNG files one after another on the standard
     * input, at the film's frame rate. -xerror: without it ffmpeg skips a
     * frame it cannot decode and still succeeds, with a short video. */
    int ok = add(cmd, s->ffmpeg) && add(cmd, "-hide_banner") && add(cmd, "-loglevel") && add(cmd, "error") &&
             add(cmd, "-xerror") && add(cmd, "-y") && add(cmd, "-f") && add(cmd, "image2pipe") &&
             add(cmd, "-framerate") && add(cmd, s->fps) && add(cmd, "-c:v") && add(cmd, "png") &&
             add(cmd, "-i") && add(cmd, "pipe:0");
    if (ok && c->pix_fmt)
        ok = yuv_filter(cmd, s, c->pix_fmt) && add(cmd, "-vf") && add(cmd, cmd->filter);
    ok = ok && add(cmd, "-c:v") && add(cmd, c->encoder);
    if (ok && c->default_crf)
        ok = add(cmd, "-crf") && add(cmd, cmd->crf);
    if (ok && s->codec == VIDEO_H265)
        /* libx265 prints its own banner and statistics whatever ffmpeg's
         * log level; Apple's players want HEVC tagged hvc1, not hev1. */
        ok = add(cmd, "-x265-params") && add(cmd, "log-level=error") && add(cmd, "-tag:v") && add(cmd, "hvc1");
    if (ok && s->codec == VIDEO_PRORES)
        ok = add(cmd, "-profile:v") && add(cmd, "3"); /* 422 HQ */
    if (ok && c->pix_fmt)
        ok = add(cmd, "-pix_fmt") && add(cmd, c->pix_fmt);
    if (ok && strcmp(c->muxer, "mp4") == 0)
        /* The index at the front, so a browser can start playing at once. */
        ok = add(cmd, "-movflags") && add(cmd, "+faststart");
    /* The container is named, not guessed from the (temporary) name. */
    return ok && add(cmd, "-f") && add(cmd, c->muxer) && add(cmd, cmd->output);
}
