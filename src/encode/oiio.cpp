// The OpenImageIO shim: the project's only C++, kept to what OpenImageIO's
// C++ API needs, built as a module of its own (liborrery-oiio.so) that
// encode/oiio_load.c loads on first use, so that a program that writes no
// such image never loads OpenImageIO and its two hundred libraries (whose
// static initialisers start threads: under `ulimit -v` they aborted even
// `orrery --version`). Every entry point catches every exception and turns
// it into an orr_status; nothing here prints. See encode/oiio.h.
#include <OpenImageIO/imageio.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <memory>
#include <new>
#include <string>
#include <system_error>
#include <vector>

// Most of the project's headers are plain C, without extern "C" guards.
extern "C" {
#include "core/error.h"
#include "core/atomic.h"
#include "encode/oiio.h"
#include "encode/oiio_module.h"
#include "core/plane.h"
}

namespace {

using OIIO::ImageInput;
using OIIO::ImageOutput;
using OIIO::ImageSpec;
using OIIO::TypeDesc;

// Enough channels for any real picture; guards the size arithmetic.
constexpr int max_channels = 1024;

// OpenImageIO keeps, besides each reader's and writer's own message, one
// per thread for failures to create them, and may complain on stderr about
// messages never collected. So every failure collects both, and a success
// clears the per-thread one too (a format probe may leave one).
std::string collect_errors(const std::string &own)
{
    std::string global = OIIO::geterror();
    std::string msg = own.empty() ? global : own;
    while (!msg.empty() && (msg.back() == '\n' || msg.back() == ' '))
        msg.pop_back();
    return msg.empty() ? std::string("no reason given") : msg;
}

// Removes the temporary file unless it was renamed into place, whatever way
// the writer leaves (error return or exception).
struct atomic_guard {
    orr_atomic_file *af;
    ~atomic_guard() { orr_atomic_abort(af); }
};

// Memory from malloc, freed unless released, so no exception leaks it.
struct free_deleter {
    void operator()(void *p) const { std::free(p); }
};
using float_buffer = std::unique_ptr<float[], free_deleter>;

// The PNG writer's rule (docs/output.md): clip to [0, 1], NaN to 0, round to
// the nearest code, in double so 16-bit codes round exactly.
unsigned quantize(float v, unsigned max)
{
    if (!(v > 0))
        return 0;
    if (v >= 1)
        return max;
    return static_cast<unsigned>(static_cast<double>(v) * max + 0.5);
}

void add_metadata(ImageSpec &spec, const orr_image_meta *meta, int bits)
{
    size_t len = orr_image_meta_text(meta, nullptr, 0);
    std::string text(len + 1, '\0');
    orr_image_meta_text(meta, &text[0], text.size());
    text.resize(len);
    spec.attribute("ImageDescription", text);
    spec.attribute("Software", orr_image_meta_software(meta));
    // Integer samples hold display (sRGB) codes, floats linear light.
    spec.attribute("oiio:ColorSpace", bits == 32 ? "Linear" : "sRGB");
    if (!meta)
        return;
    // The same names as the EXR writer's (exr.c), for formats that keep any
    // attribute (OpenEXR, PNG text); TIFF and JPEG keep the description.
    if (meta->scene && meta->scene[0]) {
        spec.attribute("DocumentName", meta->scene);
        spec.attribute("orrery:scene", meta->scene);
    }
    if (meta->projection && meta->projection[0])
        spec.attribute("orrery:projection", meta->projection);
    if (meta->has_frame)
        spec.attribute("orrery:frame", static_cast<int>(meta->frame));
    if (meta->has_time)
        spec.attribute("orrery:time", TypeDesc::DOUBLE, &meta->time);
    if (meta->has_camera) {
        spec.attribute("orrery:cameraPosition", TypeDesc(TypeDesc::DOUBLE, TypeDesc::VEC3, TypeDesc::POINT),
                       meta->cam_pos);
        static const char *const quat_names[4] = {"orrery:cameraQuatW", "orrery:cameraQuatX",
                                                  "orrery:cameraQuatY", "orrery:cameraQuatZ"};
        for (int i = 0; i < 4; i++)
            spec.attribute(quat_names[i], TypeDesc::DOUBLE, &meta->cam_quat[i]);
    }
    for (int i = 0; i < meta->nextra; i++)
        spec.attribute(std::string("orrery:") + meta->extra_key[i], meta->extra_value[i]);
}

orr_status check_write_args(const char *path, const float *pixels, int width, int height, int nchannels,
                            const char *const *names, int bits, const orr_image_meta *meta, orr_error *err)
{
    if (!path || !path[0])
        return orr_fail(err, ORR_ERR_USAGE, "image output: no file name given");
    if (bits != 8 && bits != 16 && bits != 32)
        return orr_fail(err, ORR_ERR_USAGE, "%s: bits per sample must be 8, 16 or 32 (float), not %d", path, bits);
    if (width <= 0 || height <= 0 || !pixels)
        return orr_fail(err, ORR_ERR_USAGE, "%s: empty image (%d x %d)", path, width, height);
    if (nchannels < 1 || nchannels > max_channels)
        return orr_fail(err, ORR_ERR_USAGE, "%s: %d channels (1 to %d allowed)", path, nchannels, max_channels);
    if (static_cast<size_t>(width) * static_cast<size_t>(height) > SIZE_MAX / sizeof(float) / max_channels)
        return orr_fail(err, ORR_ERR_USAGE, "%s: image too large (%d x %d)", path, width, height);
    for (int c = 0; names && c < nchannels; c++)
        if (!names[c] || !names[c][0])
            return orr_fail(err, ORR_ERR_USAGE, "%s: channel %d has no name", path, c + 1);
    return orr_image_meta_check(meta, path, err);
}

// Refusals made before any file exists, for writers that would otherwise
// not write a file at all, drop channels silently, or abort the process
// (OpenImageIO 2.4's DPX writer asserts on 2 or more than 4 channels, though
// it says it takes any number).
orr_status check_format(ImageOutput *out, const char *path, int nchannels, orr_error *err)
{
    const char *format = out->format_name();
    if (!std::strcmp(format, "null") || !std::strcmp(format, "term"))
        return orr_fail(err, ORR_ERR_USAGE, "%s: OpenImageIO's \"%s\" writer writes no file", path, format);
    if (nchannels > 4 && !out->supports("nchannels"))
        return orr_fail(err, ORR_ERR_USAGE, "%s: the %s format holds at most 4 channels, not %d", path, format,
                        nchannels);
    if (!std::strcmp(format, "dpx") && nchannels != 1 && nchannels != 3 && nchannels != 4)
        return orr_fail(err, ORR_ERR_USAGE, "%s: the dpx format holds 1, 3 or 4 channels, not %d", path,
                        nchannels);
    return ORR_OK;
}

orr_status write_image(const char *path, const float *pixels, int width, int height, int nchannels,
                       const char *const *names, int bits, const orr_image_meta *meta, orr_error *err)
{
    orr_status st = check_write_args(path, pixels, width, height, nchannels, names, bits, meta, err);
    if (st != ORR_OK)
        return st;
    // Declared before the writer so that the writer is closed (on any way
    // out) before the temporary file is removed.
    orr_atomic_file af;
    std::memset(&af, 0, sizeof af);
    atomic_guard guard{&af};
    // The writer is found from the final name, before any file exists, so
    // an unknown extension leaves nothing behind.
    std::unique_ptr<ImageOutput> out = ImageOutput::create(path);
    if (!out)
        return orr_fail(err, ORR_ERR_USAGE, "%s: no image format for this file name: %s", path,
                        collect_errors("").c_str());
    const char *format = out->format_name();
    st = check_format(out.get(), path, nchannels, err);
    if (st != ORR_OK)
        return st;
    TypeDesc type = bits == 8 ? TypeDesc::UINT8 : bits == 16 ? TypeDesc::UINT16 : TypeDesc::FLOAT;
    ImageSpec spec(width, height, nchannels, type);
    if (names)
        for (int c = 0; c < nchannels; c++)
            spec.channelnames[c] = names[c];
    add_metadata(spec, meta, bits);

    size_t n = static_cast<size_t>(width) * static_cast<size_t>(height) * static_cast<size_t>(nchannels);
    std::vector<uint8_t> codes8;
    std::vector<uint16_t> codes16;
    const void *data = pixels;
    if (bits == 8) {
        codes8.resize(n);
        for (size_t i = 0; i < n; i++)
            codes8[i] = static_cast<uint8_t>(quantize(pixels[i], 255));
        data = codes8.data();
    } else if (bits == 16) {
        codes16.resize(n);
        for (size_t i = 0; i < n; i++)
            codes16[i] = static_cast<uint16_t>(quantize(pixels[i], 65535));
        data = codes16.data();
    }

    st = orr_atomic_begin(&af, path, err);
    if (st != ORR_OK)
        return st;
    // The temporary name has no extension; the writer was chosen already.
    if (!out->open(af.temp_path, spec))
        return orr_fail(err, ORR_ERR_IO, "%s: cannot write %s file: %s", path, format,
                        collect_errors(out->geterror()).c_str());
    bool ok = out->write_image(type, data);
    ok = out->close() && ok;
    if (!ok)
        return orr_fail(err, ORR_ERR_IO, "%s: cannot write %s file: %s", path, format,
                        collect_errors(out->geterror()).c_str());
    OIIO::geterror(); // clear anything a format probe left
    return orr_atomic_commit(&af, err);
}

// Opens path for reading into `in`.
orr_status open_input(const char *path, std::unique_ptr<ImageInput> &in, orr_error *err)
{
    if (!path || !path[0])
        return orr_fail(err, ORR_ERR_USAGE, "image input: no file name given");
    in = ImageInput::open(path);
    if (!in)
        return orr_fail(err, ORR_ERR_IO, "%s: cannot read image: %s", path, collect_errors("").c_str());
    return ORR_OK;
}

orr_status read_image(const char *path, float **pixels, int *width, int *height, int *nchannels,
                      std::vector<std::string> *names, orr_error *err)
{
    std::unique_ptr<ImageInput> in;
    orr_status st = open_input(path, in, err);
    if (st != ORR_OK)
        return st;
    const ImageSpec &spec = in->spec();
    if (spec.width <= 0 || spec.height <= 0 || spec.nchannels < 1 || spec.nchannels > max_channels)
        return orr_fail(err, ORR_ERR_FORMAT, "%s: unusable image size %d x %d x %d channels", path, spec.width,
                        spec.height, spec.nchannels);
    if (spec.depth > 1)
        return orr_fail(err, ORR_ERR_FORMAT, "%s: volume images (depth %d) are not supported", path, spec.depth);
    size_t n = static_cast<size_t>(spec.width) * static_cast<size_t>(spec.height);
    if (n > SIZE_MAX / sizeof(float) / static_cast<size_t>(spec.nchannels))
        return orr_fail(err, ORR_ERR_FORMAT, "%s: image too large (%d x %d)", path, spec.width, spec.height);
    n *= static_cast<size_t>(spec.nchannels);
    float_buffer buf(static_cast<float *>(orr_malloc(n * sizeof(float), "image pixels", err)));
    if (!buf)
        return ORR_ERR_NOMEM;
    if (!in->read_image(0, 0, 0, spec.nchannels, TypeDesc::FLOAT, buf.get()))
        return orr_fail(err, ORR_ERR_IO, "%s: cannot read %s file: %s", path, in->format_name(),
                        collect_errors(in->geterror()).c_str());
    if (names)
        *names = spec.channelnames;
    *pixels = buf.release();
    *width = spec.width;
    *height = spec.height;
    *nchannels = spec.nchannels;
    in->close();
    OIIO::geterror();
    return ORR_OK;
}

orr_status read_planes(const char *path, orr_plane **planes, int *nplanes, orr_error *err)
{
    float *raw = nullptr;
    int w = 0, h = 0, nch = 0;
    std::vector<std::string> names;
    orr_status st = read_image(path, &raw, &w, &h, &nch, &names, err);
    if (st != ORR_OK)
        return st;
    float_buffer pixels(raw);
    orr_plane *p = static_cast<orr_plane *>(orr_calloc(static_cast<size_t>(nch), sizeof *p, "image planes", err));
    if (!p)
        return ORR_ERR_NOMEM;
    size_t npix = static_cast<size_t>(w) * static_cast<size_t>(h);
    for (int c = 0; c < nch; c++) {
        // orr_plane_alloc copies the name: cut it to fit rather than fail.
        char name[ORR_PLANE_NAME_MAX];
        std::snprintf(name, sizeof name, "%s", c < static_cast<int>(names.size()) ? names[c].c_str() : "");
        st = orr_plane_alloc(&p[c], w, h, name, "", err);
        if (st != ORR_OK) {
            for (int k = 0; k < c; k++)
                orr_plane_free(&p[k]);
            std::free(p);
            return st;
        }
        for (size_t i = 0; i < npix; i++)
            p[c].data[i] = pixels[i * static_cast<size_t>(nch) + static_cast<size_t>(c)];
    }
    *planes = p;
    *nplanes = nch;
    return ORR_OK;
}

orr_status get_attribute(const char *path, const char *name, char *buf, size_t size, orr_error *err)
{
    if (!buf || size == 0 || !name || !name[0])
        return orr_fail(err, ORR_ERR_USAGE, "%s: no attribute name or no room for its value", path ? path : "");
    buf[0] = '\0';
    std::unique_ptr<ImageInput> in;
    orr_status st = open_input(path, in, err);
    if (st != ORR_OK)
        return st;
    const ImageSpec &spec = in->spec();
    OIIO::ParamValue tmp;
    const OIIO::ParamValue *p = spec.find_attribute(name, tmp); // also "width", "datawindow", ...
    std::string value;
    if (p) {
        value = p->get_string(1024);
    } else if (OIIO::Strutil::iequals(name, "format")) {
        value = spec.format.c_str(); // the sample type, which is no attribute
    } else {
        in->close();
        return orr_fail(err, ORR_ERR_FORMAT, "%s: no attribute %s", path, name);
    }
    std::snprintf(buf, size, "%s", value.c_str());
    in->close();
    OIIO::geterror();
    return ORR_OK;
}

// Runs f, turning any exception into an orr_status with path in the message.
template <class F> orr_status guarded(const char *path, orr_error *err, F f)
{
    const char *name = path ? path : "(no name)";
    try {
        return f();
    } catch (const std::bad_alloc &) {
        return orr_fail(err, ORR_ERR_NOMEM, "%s: out of memory in OpenImageIO", name);
    } catch (const std::system_error &e) {
        // A thread OpenImageIO could not start (EAGAIN), most often.
        return orr_fail(err, ORR_ERR_NOMEM, "%s: OpenImageIO ran out of a system resource: %s (threads or address "
                        "space: see ulimit -u and ulimit -v)", name, e.what());
    } catch (const std::exception &e) {
        return orr_fail(err, ORR_ERR_INTERNAL, "%s: OpenImageIO failed: %s", name, e.what());
    } catch (...) {
        return orr_fail(err, ORR_ERR_INTERNAL, "%s: OpenImageIO failed with an unknown exception", name);
    }
}

orr_status module_write(const char *path, const float *pixels, int width, int height, int nchannels,
                        const char *const *channel_names, int bits, const orr_image_meta *meta, orr_error *err)
{
    return guarded(path, err, [&] {
        return write_image(path, pixels, width, height, nchannels, channel_names, bits, meta, err);
    });
}

orr_status module_read(const char *path, float **pixels, int *width, int *height, int *nchannels, orr_error *err)
{
    return guarded(path, err, [&] { return read_image(path, pixels, width, height, nchannels, nullptr, err); });
}

orr_status module_read_planes(const char *path, orr_plane **planes, int *nplanes, orr_error *err)
{
    return guarded(path, err, [&] { return read_planes(path, planes, nplanes, err); });
}

orr_status module_get_attribute(const char *path, const char *name, char *buf, size_t size, orr_error *err)
{
    return guarded(path, err, [&] { return get_attribute(path, name, buf, size, err); });
}

const orr_oiio_module the_module = {ORR_OIIO_MODULE_VERSION, module_write, module_read, module_read_planes,
                                    module_get_attribute};

} // namespace

// The module's one exported symbol (src/encode/oiio_module.map).
extern "C" const orr_oiio_module *orr_oiio_module_entry(void) { return &the_module; }
