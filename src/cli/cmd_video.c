/* orrery video SCENE.yaml [--set KEY=VALUE ...] [-o DIR] [--view NAME] [--codec C] [--crf N]
 *                         [--fps F] [--frames N] [--out FILE] [--force] [--quiet]
 * Encodes the frames a render wrote (DIR/NAME_0000.png, ...) into a video
 * with ffmpeg, one per view: the frames are checked here and written to
 * ffmpeg's standard input; the ffmpeg command is built in video_command.c. */
#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <getopt.h>
#include <signal.h>
#include <spawn.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "cli/cli.h"
#include "render/animation.h"
#include "cli/video_command.h"
#include "core/numbers.h"
#include "core/atomic.h"
#include "render/plan.h"
#include "scene/scene.h"

extern char **environ;

static const char video_help[] =
    "usage: orrery video SCENE.yaml [--set KEY=VALUE ...] [-o DIR] [--view NAME]\n"
    "                    [--codec h264|h265|prores|png] [--crf N] [--fps F] [--frames N]\n"
    "                    [--out FILE] [--force] [--quiet]\n"
    "\n"
    "Encodes the frames that `orrery render` wrote for an animation,\n"
    "DIR/NAME_0000.png, DIR/NAME_0001.png, ... (NAME is the view's\n"
    "output.name, DIR its output.dir), into one video per view with ffmpeg,\n"
    "DIR/NAME.mp4 (DIR/NAME.mov for prores and png), at animation.fps. The\n"
    "scene's animation.frames frames must all be there; for a still scene it\n"
    "takes the frames present from 0 up to the first missing one.\n"
    "\n"
    "  --set KEY=VALUE   override a scene key, as for render (repeatable)\n"
    "  -o, --output DIR  the folder the frames are in (overrides output.dir); the video goes there too\n"
    "  --view NAME       only this view of a scene with views (default: every view)\n"
    "  --codec CODEC     h264   (default) libx264, yuv420p, MP4: plays anywhere\n"
    "                    h265   libx265, yuv420p, tagged hvc1, MP4: smaller files\n"
    "                    prores ProRes 422 HQ (prores_ks profile 3), yuv422p10le, MOV: masters\n"
    "                    png    the PNG frames, lossless, in a MOV\n"
    "                    h264 and h265 need even sizes: odd frames are padded by one\n"
    "                    black pixel on the right and/or bottom (a note says so); frames\n"
    "                    that need a level above 5.2, which many players refuse, get a\n"
    "                    warning (h264: over 3072x3072 at 30 fps): for dome masters of 4K\n"
    "                    and more use prores or png\n"
    "  --crf N           quality of h264 and h265, 0 (lossless) to 51 (default 18 for h264,\n"
    "                    23 for h265; lower is better and bigger)\n"
    "  --fps F           frames per second, e.g. 24, 29.97 or 30000/1001 (default: animation.fps)\n"
    "  --frames N        require exactly frames 0 to N-1 (an error names the first missing one;\n"
    "                    default: animation.frames when the scene is a run of frames)\n"
    "  --out FILE        the video's name (one view only); .mp4 for h264/h265, .mov otherwise\n"
    "  --force           replace an existing video (otherwise it is an error)\n"
    "  -q, --quiet       no notes or summary, only errors and warnings\n"
    "  -h, --help        this text\n"
    "\n"
    "Needs ffmpeg on the PATH (scripts/install-deps.sh installs it). The video is\n"
    "written to a temporary name and renamed when ffmpeg succeeds, so a failed run\n"
    "leaves nothing behind. Exit status: 0 success, 1 runtime failure, 2 usage error.\n";

typedef struct video_options {
    const char *scene_path, *out_dir, *view, *out_file;
    const char **sets;
    int nsets;
    video_codec codec;
    int crf;          /* -1: the codec's default */
    char fps[48];     /* as ffmpeg takes it */
    int fps_given;    /* --fps was given; otherwise the scene's animation.fps */
    long long frames; /* 0: count the frames present */
    int force, quiet;
} video_options;

/* A view's frames: their count, how they are named (the digits of their
 * numbers found on disk) and their size. */
typedef struct frame_set {
    char dir[ORR_PATH_MAX];
    char name[ORR_NAME_MAX];
    orr_frame_naming naming; /* the view's output.frame_* keys */
    long count;
    unsigned width, height;
} frame_set;

/* --fps: a positive number up to 1000, or a ratio of whole numbers such as
 * 30000/1001 (NTSC), written back in a form ffmpeg reads exactly. */
static int parse_fps(const char *text, char *out, size_t size)
{
    char *end;
    if (strchr(text, '/')) {
        long long num = strtoll(text, &end, 10);
        if (end == text || *end != '/')
            return 0;
        const char *den_text = end + 1;
        long long den = strtoll(den_text, &end, 10);
        if (end == den_text || *end || num <= 0 || den <= 0 || num > 1000LL * den || num > 1000000000LL ||
            den > 1000000000LL)
            return 0;
        snprintf(out, size, "%lld/%lld", num, den);
        return 1;
    }
    double v = orr_strtod(text, &end);
    if (end == text || *end || !(v > 0 && v <= 1000))
        return 0;
    orr_snprintf(out, size, "%.10g", v);
    return 1;
}

enum { OPT_SET = 256, OPT_VIEW, OPT_CODEC, OPT_CRF, OPT_FPS, OPT_FRAMES, OPT_OUT, OPT_FORCE };

static const struct option video_options_long[] = {
    {"set", required_argument, NULL, OPT_SET},       {"output", required_argument, NULL, 'o'},
    {"view", required_argument, NULL, OPT_VIEW},     {"codec", required_argument, NULL, OPT_CODEC},
    {"crf", required_argument, NULL, OPT_CRF},       {"fps", required_argument, NULL, OPT_FPS},
    {"frames", required_argument, NULL, OPT_FRAMES}, {"out", required_argument, NULL, OPT_OUT},
    {"force", no_argument, NULL, OPT_FORCE},         {"quiet", no_argument, NULL, 'q'},
    {"help", no_argument, NULL, 'h'},                {NULL, 0, NULL, 0},
};

/* One option; EXIT_OK, -1 after --help, or a usage error. */
static int take_option(int code, const char *v, video_options *o)
{
    long long n;
    switch (code) {
    case 'h':
        fputs(video_help, stdout);
        return -1;
    case OPT_SET:
        o->sets[o->nsets++] = v;
        return EXIT_OK;
    case 'o':
        o->out_dir = v;
        return EXIT_OK;
    case OPT_VIEW:
        o->view = v;
        return EXIT_OK;
    case OPT_OUT:
        o->out_file = v;
        return EXIT_OK;
    case OPT_CODEC:
        if (!video_codec_parse(v, &o->codec))
            return cli_usage_error("video", "--codec %s: unknown codec (h264, h265, prores or png)", v);
        return EXIT_OK;
    case OPT_CRF:
        if (cli_count_option("video", "--crf", v, 0, 51, &n) != EXIT_OK)
            return EXIT_USAGE;
        o->crf = (int)n;
        return EXIT_OK;
    case OPT_FPS:
        o->fps_given = 1;
        if (!parse_fps(v, o->fps, sizeof o->fps))
            return cli_usage_error("video", "--fps %s: expected a rate above 0 and up to 1000, e.g. 24, "
                                            "29.97 or 30000/1001", v);
        return EXIT_OK;
    case OPT_FRAMES:
        if (cli_count_option("video", "--frames", v, 1, 100000000, &n) != EXIT_OK)
            return EXIT_USAGE;
        o->frames = n;
        return EXIT_OK;
    case OPT_FORCE:
        o->force = 1;
        return EXIT_OK;
    case 'q':
        o->quiet = 1;
        return EXIT_OK;
    case CLI_OPERAND:
        if (o->scene_path)
            return cli_usage_error("video", "one scene file at a time (got '%s' and '%s')", o->scene_path, v);
        o->scene_path = v;
        return EXIT_OK;
    default:
        return EXIT_USAGE; /* CLI_BAD: already told */
    }
}

static int parse_options(int argc, char **argv, video_options *o)
{
    o->codec = VIDEO_H264;
    o->crf = -1;
    snprintf(o->fps, sizeof o->fps, "30");
    const char *value;
    int code;
    cli_options_begin();
    while ((code = cli_next_option("video", argc, argv, "ho:q", video_options_long, &value)) != -1) {
        int st = take_option(code, value, o);
        if (st != EXIT_OK)
            return st;
    }
    if (!o->scene_path)
        return cli_usage_error("video", "no scene file given");
    if (o->crf >= 0 && !video_codec_has_crf(o->codec))
        return cli_usage_error("video", "--crf applies to h264 and h265, not %s", video_codec_name(o->codec));
    if (o->crf < 0)
        o->crf = video_codec_default_crf(o->codec);
    return EXIT_OK;
}

/* The full path of program on the PATH, as execvp would find it. */
static int find_program(const char *program, char *out, size_t size)
{
    const char *path = getenv("PATH");
    if (!path)
        path = "/usr/local/bin:/usr/bin:/bin";
    while (1) {
        size_t len = strcspn(path, ":");
        int n = len ? snprintf(out, size, "%.*s/%s", (int)len, path, program) : snprintf(out, size, "%s", program);
        struct stat st;
        if (n > 0 && (size_t)n < size && stat(out, &st) == 0 && S_ISREG(st.st_mode) && access(out, X_OK) == 0)
            return 1;
        if (!path[len])
            return 0;
        path += len + 1;
    }
}

static int frame_path(char *out, size_t size, const frame_set *fs, long frame)
{
    char name[ORR_NAME_MAX];
    orr_error ignored;
    if (orr_frame_name_fixed(&fs->naming, fs->name, frame, name, sizeof name, &ignored))
        return 0;
    int n = snprintf(out, size, "%s/%s.png", fs->dir, name);
    return n > 0 && (size_t)n < size;
}

static int is_file(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0 && S_ISREG(st.st_mode);
}

/* Reads a PNG's size from its IHDR chunk, which the format puts first. */
static orr_status png_size(const char *path, unsigned *width, unsigned *height, orr_error *err)
{
    static const unsigned char signature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    unsigned char head[24];
    FILE *fp = fopen(path, "rb");
    if (!fp)
        return orr_fail(err, ORR_ERR_IO, "cannot open frame %s: %s", path, strerror(errno));
    size_t got = fread(head, 1, sizeof head, fp);
    fclose(fp);
    if (got < sizeof head || memcmp(head, signature, 8) != 0 || memcmp(head + 12, "IHDR", 4) != 0)
        return orr_fail(err, ORR_ERR_FORMAT, "frame %s is not a PNG file", path);
    *width = (unsigned)head[16] << 24 | (unsigned)head[17] << 16 | (unsigned)head[18] << 8 | head[19];
    *height = (unsigned)head[20] << 24 | (unsigned)head[21] << 16 | (unsigned)head[22] << 8 | head[23];
    /* The codecs stop far below this (h264 at 8192 or so); the bound keeps
     * the padded size within an int. */
    if (*width == 0 || *height == 0 || *width > 1u << 20 || *height > 1u << 20)
        return orr_fail(err, ORR_ERR_FORMAT, "frame %s: its header gives a size of %ux%u, which no video takes",
                        path, *width, *height);
    return ORR_OK;
}

/* The largest frame index (0 for the first frame, whatever its number)
 * among DIR/NAME<separator><digits>.png, -1 when none: to tell the user
 * about frames left out after a gap. */
static long last_frame_number(const frame_set *fs)
{
    DIR *d = opendir(fs->dir);
    long last = -1;
    size_t name_len = strlen(fs->name), sep_len = strlen(fs->naming.separator);
    for (struct dirent *e; d && (e = readdir(d));) {
        const char *f = e->d_name;
        if (strncmp(f, fs->name, name_len) != 0 || strncmp(f + name_len, fs->naming.separator, sep_len) != 0)
            continue;
        const char *digits = f + name_len + sep_len;
        size_t nd = strspn(digits, "0123456789");
        if ((int)nd == fs->naming.digits && strcmp(digits + nd, ".png") == 0) {
            long n = (long)(strtoll(digits, NULL, 10) - fs->naming.start);
            if (n > last)
                last = n;
        }
    }
    if (d)
        closedir(d);
    return last;
}

/* Finds the view's frames: exactly 0..frames-1 when frames > 0, otherwise
 * those present from 0 up to the first gap. Checks that every one is a PNG
 * of the first one's size. */
static orr_status find_frames(frame_set *fs, long long frames, orr_error *err)
{
    char path[ORR_PATH_MAX];
    fs->count = 0;
    if (frames > 0) {
        fs->naming.digits = orr_frame_digits(&fs->naming, (long)frames); /* the naming contract of orrery render */
    } else {
        /* The run's length is unknown, so neither is the width of its frame
         * numbers: the first width from the scene's whose frame 0 exists. */
        int least = fs->naming.digits;
        for (int d = least; d <= 18; d++) {
            fs->naming.digits = d;
            if (frame_path(path, sizeof path, fs, 0) && is_file(path))
                break;
            fs->naming.digits = least;
        }
    }
    long limit = frames > 0 ? (long)frames : 1000000000L;
    for (long k = 0; k < limit; k++) {
        if (!frame_path(path, sizeof path, fs, k))
            return orr_fail(err, ORR_ERR_USAGE, "frame path is too long: %.200s/%s_...", fs->dir, fs->name);
        if (!is_file(path)) {
            if (k == 0)
                return orr_fail(err, ORR_ERR_IO, "no frames found: %s is missing (render the animation first)",
                                path);
            if (frames > 0)
                return orr_fail(err, ORR_ERR_IO, "--frames %lld: frame %ld is missing: %s", frames, k, path);
            break;
        }
        unsigned w = 0, h = 0;
        orr_status st = png_size(path, &w, &h, err);
        if (st)
            return st;
        if (k == 0) {
            fs->width = w;
            fs->height = h;
        } else if (w != fs->width || h != fs->height) {
            return orr_fail(err, ORR_ERR_FORMAT, "frame %s is %ux%u but frame 0 is %ux%u: a video needs one size",
                            path, w, h, fs->width, fs->height);
        }
        fs->count = k + 1;
    }
    return ORR_OK;
}

/* Whether name ends in .ext, in any case. */
static int has_extension(const char *name, const char *ext)
{
    size_t n = strlen(name), e = strlen(ext);
    return n > e + 1 && name[n - e - 1] == '.' && strcasecmp(name + n - e, ext) == 0;
}

/* Writes all of buf to fd; returns errno on failure (EPIPE when ffmpeg has
 * stopped reading). */
static int write_all(int fd, const unsigned char *buf, size_t n)
{
    while (n > 0) {
        ssize_t w = write(fd, buf, n);
        if (w < 0 && errno == EINTR)
            continue;
        if (w < 0)
            return errno;
        buf += w;
        n -= (size_t)w;
    }
    return 0;
}

/* Copies the view's frames, in order, to fd. Returns ORR_OK when all were
 * sent or ffmpeg stopped reading (its exit status then says why). */
static orr_status send_frames(int fd, const frame_set *fs, orr_error *err)
{
    enum { BUFFER = 1 << 20 };
    unsigned char *buf = malloc(BUFFER);
    if (!buf)
        return orr_fail(err, ORR_ERR_NOMEM, "out of memory");
    char path[ORR_PATH_MAX];
    orr_status st = ORR_OK;
    int broken_pipe = 0;
    for (long k = 0; !st && !broken_pipe && k < fs->count; k++) {
        FILE *fp = frame_path(path, sizeof path, fs, k) ? fopen(path, "rb") : NULL;
        if (!fp) {
            st = orr_fail(err, ORR_ERR_IO, "cannot open frame %s: %s", path, strerror(errno));
            break;
        }
        size_t got;
        while (!broken_pipe && (got = fread(buf, 1, BUFFER, fp)) > 0) {
            int e = write_all(fd, buf, got);
            if (e == EPIPE)
                broken_pipe = 1;
            else if (e)
                st = orr_fail(err, ORR_ERR_IO, "sending frame %s to ffmpeg: %s", path, strerror(e));
            if (e)
                break;
        }
        if (!st && !broken_pipe && ferror(fp))
            st = orr_fail(err, ORR_ERR_IO, "cannot read frame %s", path);
        fclose(fp);
    }
    free(buf);
    return st;
}

/* Runs the command with the frames on its standard input and waits for it. */
static orr_status run_ffmpeg(const video_command *cmd, const frame_set *fs, const char *output, orr_error *err)
{
    int fds[2];
    if (pipe(fds) != 0)
        return orr_fail(err, ORR_ERR_IO, "cannot make a pipe to ffmpeg: %s", strerror(errno));
    /* ffmpeg gets the reading end as its standard input and nothing else. */
    fcntl(fds[0], F_SETFD, FD_CLOEXEC);
    fcntl(fds[1], F_SETFD, FD_CLOEXEC);
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_adddup2(&actions, fds[0], STDIN_FILENO); /* dup2 clears close-on-exec */
    pid_t pid;
    int rc = posix_spawn(&pid, cmd->argv[0], &actions, NULL, (char *const *)cmd->argv, environ);
    posix_spawn_file_actions_destroy(&actions);
    close(fds[0]);
    if (rc != 0) {
        close(fds[1]);
        return orr_fail(err, ORR_ERR_IO, "cannot run %s: %s", cmd->argv[0], strerror(rc));
    }
    /* When ffmpeg fails it stops reading: the write then fails with EPIPE
     * instead of the signal ending orrery. */
    struct sigaction ignore = {.sa_handler = SIG_IGN}, previous;
    sigemptyset(&ignore.sa_mask);
    sigaction(SIGPIPE, &ignore, &previous);
    orr_status st = send_frames(fds[1], fs, err);
    if (st)
        kill(pid, SIGTERM); /* it would otherwise finish a video without the remaining frames */
    close(fds[1]);
    int status;
    pid_t waited;
    while ((waited = waitpid(pid, &status, 0)) < 0 && errno == EINTR)
        ;
    sigaction(SIGPIPE, &previous, NULL);
    if (st)
        return st;
    if (waited < 0)
        return orr_fail(err, ORR_ERR_INTERNAL, "waiting for ffmpeg: %s", strerror(errno));
    if (WIFEXITED(status) && WEXITSTATUS(status) == 0)
        return ORR_OK;
    if (WIFSIGNALED(status))
        return orr_fail(err, ORR_ERR_IO, "ffmpeg was killed by signal %d while writing %s", WTERMSIG(status),
                        output);
    return orr_fail(err, ORR_ERR_IO, "ffmpeg failed (exit status %d) writing %s; its messages are above",
                    WEXITSTATUS(status), output);
}

/* Encodes one view's frames into output. */
/* The frame rate as a number: "30", "29.97" or "30000/1001". */
static double fps_value(const char *fps)
{
    char *end;
    double v = orr_strtod(fps, &end);
    if (*end == '/') {
        double den = orr_strtod(end + 1, NULL);
        v = den > 0 ? v / den : v;
    }
    return v;
}

/* Warns when the frames need a level of H.264 or H.265 above 5.2, which
 * many players and hardware decoders refuse to play (the encoders choose
 * the level from the size, and go on to 6.x). A warning, not an error:
 * a projection server or a software player may well take it. */
static void warn_level(const video_options *o, int width, int height)
{
    int level = video_level(o->codec, width, height, fps_value(o->fps));
    if (level >= 0 && level <= VIDEO_LEVEL_PLAYABLE)
        return;
    char need[64];
    if (level < 0)
        snprintf(need, sizeof need, "more than %s's highest level, 6.2", video_codec_name(o->codec));
    else
        snprintf(need, sizeof need, "%s level %d.%d", video_codec_name(o->codec), level / 10, level % 10);
    fprintf(stderr, "orrery: warning: %dx%d frames at %s fps need %s, and many players and hardware decoders "
                    "stop at level 5.2 (at 30 fps, square frames up to 3072x3072 with h264, 2984x2984 with "
                    "h265); for a dome master use --codec prores or the PNG frames "
                    "(docs/animation.md#codecs-for-dome-masters)\n",
            width, height, o->fps, need);
}

static orr_status encode_view(const video_options *o, const char *ffmpeg, const frame_set *fs, const char *output,
                              orr_error *err)
{
    video_settings s = {.ffmpeg = ffmpeg, .fps = o->fps, .codec = o->codec, .crf = o->crf};
    int pad_w = video_codec_needs_even_width(o->codec) && fs->width % 2;
    int pad_h = video_codec_needs_even_height(o->codec) && fs->height % 2;
    if (pad_w || pad_h) {
        s.pad_width = (int)fs->width + pad_w;
        s.pad_height = (int)fs->height + pad_h;
        if (!o->quiet)
            fprintf(stderr, "orrery: note: %s needs an even width and height; the %ux%u frames are padded "
                            "to %dx%d with black on the %s\n", video_codec_name(o->codec), fs->width, fs->height,
                    s.pad_width, s.pad_height, pad_w && pad_h ? "right and bottom" : pad_w ? "right" : "bottom");
    }
    warn_level(o, (int)fs->width + pad_w, (int)fs->height + pad_h);

    orr_atomic_file af;
    orr_status st = orr_atomic_begin(&af, output, err);
    if (st)
        return st;
    s.output = af.temp_path;
    video_command *cmd = malloc(sizeof *cmd);
    if (!cmd)
        st = orr_fail(err, ORR_ERR_NOMEM, "out of memory");
    else if (!video_command_build(cmd, &s))
        st = orr_fail(err, ORR_ERR_USAGE, "the ffmpeg command for %s is too long", output);
    else
        st = run_ffmpeg(cmd, fs, output, err);
    free(cmd);
    if (!st)
        st = orr_atomic_commit(&af, err);
    if (st)
        orr_atomic_abort(&af);
    return st;
}

/* The video's name: --out, or DIR/NAME.mp4 (.mov). */
static orr_status output_path(const video_options *o, const frame_set *fs, char *out, size_t size, orr_error *err)
{
    const char *ext = video_codec_extension(o->codec);
    if (o->out_file) {
        if (!has_extension(o->out_file, ext))
            return orr_fail(err, ORR_ERR_USAGE, "--out %s: a %s video is a .%s file; name it so", o->out_file,
                            video_codec_name(o->codec), ext);
        if (snprintf(out, size, "%s", o->out_file) >= (int)size)
            return orr_fail(err, ORR_ERR_USAGE, "--out: the name is too long");
        return ORR_OK;
    }
    if (snprintf(out, size, "%s/%s.%s", fs->dir, fs->name, ext) >= (int)size)
        return orr_fail(err, ORR_ERR_USAGE, "output path is too long: %.200s/%s.%s", fs->dir, fs->name, ext);
    return ORR_OK;
}

/* One view's video: its frames and where it goes. */
typedef struct view_job {
    frame_set frames;
    char output[ORR_PATH_MAX];
    const char *view_name; /* "" for a scene without views */
} view_job;

/* Finds a view's frames and names its video, checking everything that can
 * be checked before ffmpeg runs. */
static orr_status prepare_view(const video_options *o, const orr_output_place *view, const char *view_name,
                               view_job *job, orr_error *err)
{
    frame_set *fs = &job->frames;
    job->view_name = view_name;
    const char *dir = o->out_dir ? o->out_dir : view->dir;
    if (snprintf(fs->dir, sizeof fs->dir, "%s", dir) >= (int)sizeof fs->dir)
        return orr_fail(err, ORR_ERR_USAGE, "output directory name is too long");
    snprintf(fs->name, sizeof fs->name, "%s", view->name);
    fs->naming = view->naming;
    orr_status st = output_path(o, fs, job->output, sizeof job->output, err);
    if (st)
        return st;
    if (!o->force && is_file(job->output))
        return orr_fail(err, ORR_ERR_IO, "%s exists (--force replaces it)", job->output);
    st = find_frames(fs, o->frames, err);
    if (!st) /* never a video of two runs' frames */
        st = orr_frames_agree(fs->dir, fs->name, &fs->naming, fs->count, err);
    if (st)
        return st;
    if (o->frames == 0) {
        long last = last_frame_number(fs);
        if (last >= fs->count) {
            char missing[ORR_PATH_MAX] = "";
            if (!frame_path(missing, sizeof missing, fs, fs->count))
                snprintf(missing, sizeof missing, "frame %ld", fs->count);
            fprintf(stderr, "orrery: warning: %s is missing, so only frames 0 to %ld are encoded "
                            "(frames up to %ld exist; --frames N requires N frames)\n", missing, fs->count - 1, last);
        }
    }
    return ORR_OK;
}

static orr_status make_video(const video_options *o, const char *ffmpeg, const view_job *job, orr_error *err)
{
    const frame_set *fs = &job->frames;
    orr_status st = encode_view(o, ffmpeg, fs, job->output, err);
    if (!st && !o->quiet) {
        if (job->view_name[0])
            printf("view %s: ", job->view_name);
        printf("wrote %s: %ld frame%s of %ux%u at %s fps, %s\n", job->output, fs->count, fs->count == 1 ? "" : "s",
               fs->width, fs->height, o->fps, video_codec_name(o->codec));
    }
    return st;
}

int cmd_video(int argc, char **argv)
{
    video_options o = {0};
    o.sets = calloc((size_t)argc, sizeof *o.sets);
    if (!o.sets) {
        fprintf(stderr, "orrery: error: out of memory\n");
        return EXIT_RUNTIME;
    }
    int code = parse_options(argc, argv, &o);
    if (code != EXIT_OK) {
        free(o.sets);
        return code < 0 ? EXIT_OK : code;
    }

    orr_error err = {0};
    char ffmpeg[ORR_PATH_MAX];
    orr_scene_views *views = calloc(1, sizeof *views);
    view_job *jobs = calloc(ORR_SCENE_MAX_VIEWS, sizeof *jobs);
    orr_status st = views && jobs ? ORR_OK : orr_fail(&err, ORR_ERR_NOMEM, "out of memory");
    if (!st && !find_program("ffmpeg", ffmpeg, sizeof ffmpeg))
        st = orr_fail(&err, ORR_ERR_IO, "ffmpeg not found: install it (scripts/install-deps.sh installs it)");
    if (!st)
        st = orr_scene_load_views(views, o.scene_path, o.sets, o.nsets, &err);
    /* The scene's run: its frame rate and length, unless given here. */
    orr_run_settings run = {0};
    if (!st)
        run = orr_plan_run_settings(&views->view[0]);
    if (!st && !o.fps_given)
        orr_snprintf(o.fps, sizeof o.fps, "%.10g", run.fps);
    if (!st && o.frames == 0 && run.frames > 1)
        o.frames = run.frames;
    int chosen = -1; /* the --view, or -1 for all */
    for (int k = 0; !st && o.view && k < views->n; k++)
        if (strcmp(views->name[k], o.view) == 0)
            chosen = k;
    if (!st && o.view && chosen < 0 && !views->name[0][0])
        st = orr_fail(&err, ORR_ERR_USAGE, "--view %s: %s has no views", o.view, o.scene_path);
    else if (!st && o.view && chosen < 0) {
        char names[512] = "";
        for (int k = 0; k < views->n; k++)
            snprintf(names + strlen(names), sizeof names - strlen(names), "%s%s", k ? ", " : "", views->name[k]);
        st = orr_fail(&err, ORR_ERR_USAGE, "--view %s: %s has no such view (its views: %s)", o.view, o.scene_path,
                      names);
    }
    if (!st && o.out_file && chosen < 0 && views->n > 1)
        st = orr_fail(&err, ORR_ERR_USAGE, "--out names one video, but %s has %d views: choose one with --view",
                      o.scene_path, views->n);
    /* Every view's frames are checked before any video is made, so a view
     * with missing frames does not leave the others half done. */
    int njobs = 0;
    for (int k = 0; !st && k < views->n; k++) {
        if (chosen >= 0 && k != chosen)
            continue;
        const orr_output_place place = orr_plan_output_place(&views->view[k]);
        st = prepare_view(&o, &place, views->name[k], &jobs[njobs++], &err);
    }
    for (int j = 0; !st && j < njobs; j++)
        st = make_video(&o, ffmpeg, &jobs[j], &err);
    code = st ? cli_report_error(&err) : EXIT_OK;
    free(jobs);
    if (views)
        orr_scene_views_free(views);
    free(views);
    free(o.sets);
    return code;
}
