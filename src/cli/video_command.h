/* The ffmpeg command line of `orrery video`, built by a pure function so a
 * unit test can check it word for word (tests/unit/test_video_command.c).
 * ffmpeg reads the PNG frames from its standard input, where `orrery
 * video` writes them one after the other: so exactly the frames found are
 * encoded, in order, whatever their names (ffmpeg's own numbered-sequence
 * reader would skip over a gap to later frames, and reads '%' in names as
 * a pattern). No shell is involved: the words go to posix_spawn as they
 * are, so the output name may hold spaces, quotes or any other character. */
#ifndef ORR_CLI_VIDEO_COMMAND_H
#define ORR_CLI_VIDEO_COMMAND_H

#include <stddef.h>

typedef enum {
    VIDEO_H264,   /* libx264, yuv420p, .mp4: for playback anywhere */
    VIDEO_H265,   /* libx265, yuv420p, tagged hvc1 (as Apple players need), .mp4 */
    VIDEO_PRORES, /* prores_ks profile 3 (422 HQ), yuv422p10le, .mov: masters for editing */
    VIDEO_PNG,    /* PNG frames in a QuickTime file, .mov: lossless, the pixels as rendered */
} video_codec;

/* Parses "h264", "h265", "prores" or "png"; returns 0 when unknown. */
int video_codec_parse(const char *name, video_codec *out);
const char *video_codec_name(video_codec codec);
/* The container's file extension, without the dot: "mp4" or "mov". */
const char *video_codec_extension(video_codec codec);
/* Whether the codec takes --crf, and its default when it does. */
int video_codec_has_crf(video_codec codec);
int video_codec_default_crf(video_codec codec);
/* Whether the codec's chroma subsampling needs an even width, and height. */
int video_codec_needs_even_width(video_codec codec);
int video_codec_needs_even_height(video_codec codec);

/* The lowest level of the codec's standard whose limits hold frames of
 * width x height pixels at fps frames a second, times ten (40 is level
 * 4.0, 52 is 5.2); -1 when the frames are beyond every level; 0 for the
 * codecs without levels (prores, png). */
int video_level(video_codec codec, int width, int height, double fps);

/* The highest level most players and hardware decoders take (5.2): H.264
 * at 5.2 holds at most 36864 macroblocks a frame (4096x2304), H.265 at 5.2
 * 8912896 pixels (4096x2176); a 3600x3600 dome master needs level 6. */
#define VIDEO_LEVEL_PLAYABLE 52

typedef struct video_settings {
    const char *ffmpeg;        /* the program to run (a path, or "ffmpeg") */
    const char *fps;           /* frame rate as ffmpeg takes it: "30", "24", "30000/1001" */
    video_codec codec;
    int crf;                   /* quality for h264/h265 (lower is better); ignored by the others */
    int pad_width, pad_height; /* > 0: pad the frames on the right/bottom to this even size */
    const char *output;        /* the file ffmpeg writes (any name: the container is given with -f) */
} video_settings;

#define VIDEO_MAX_ARGS 64

typedef struct video_command {
    int argc;
    const char *argv[VIDEO_MAX_ARGS]; /* NULL-terminated, for posix_spawn */
    /* Storage for the words made here; argv points into it or into settings. */
    char crf[16], filter[256];
    char output[4096 + 8]; /* "file:" + the output */
} video_command;

/* Fills cmd with the ffmpeg command for s. Returns 0 when the command
 * would not fit (it always does for valid settings). */
int video_command_build(video_command *cmd, const video_settings *s);

#endif
