/* encode/oiio.h's functions: OpenImageIO is loaded only when a program
 * first reads or writes such an image, as the module liborrery-oiio.so
 * (oiio.cpp). Loading it with the library would load OpenImageIO's two
 * hundred libraries into every program, whose static initialisers start
 * threads (log4cplus, through OpenVDB): under `ulimit -v 400000` they
 * aborted even `orrery --version` before main. */
#define _GNU_SOURCE /* dladdr */
#include "encode/oiio.h"

#include <dlfcn.h>
#include <pthread.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "core/limits.h"
#include "encode/oiio_module.h"

#define MODULE_NAME "liborrery-oiio.so"

static pthread_once_t load_once = PTHREAD_ONCE_INIT;
static const orr_oiio_module *module;
static char load_error[ORR_PATH_MAX + 256];

/* Tries dir/MODULE_NAME; 1 when the module is loaded. */
static int try_dir(const char *dir, size_t len)
{
    char path[ORR_PATH_MAX];
    if (snprintf(path, sizeof path, "%.*s/" MODULE_NAME, (int)len, dir) >= (int)sizeof path ||
        access(path, F_OK) != 0)
        return 0; /* not here: looked for elsewhere */
    void *h = dlopen(path, RTLD_NOW | RTLD_LOCAL);
    if (!h) { /* there, but it cannot load (OpenImageIO missing, out of memory): why */
        snprintf(load_error, sizeof load_error, "%s", dlerror());
        return 0;
    }
    const orr_oiio_module *(*entry)(void) = (const orr_oiio_module *(*)(void))dlsym(h, "orr_oiio_module_entry");
    const orr_oiio_module *m = entry ? entry() : NULL;
    if (!m || m->version != ORR_OIIO_MODULE_VERSION) {
        snprintf(load_error, sizeof load_error, "%s is of another build of orrery (rebuild or reinstall it)", path);
        dlclose(h);
        return 0;
    }
    module = m;
    return 1;
}

/* The module is looked for beside the code that asks for it (liborrery.so,
 * or a program linked to liborrery.a: the build folder, an installed
 * libdir), in the folder above it (the build folder's tests/ and
 * examples/), in the libdir beside an installed bin/ (an installed tree
 * moved elsewhere), and in the libdir it is installed to. */
static void load(void)
{
    Dl_info info;
    if (dladdr((void *)&load, &info) && info.dli_fname) {
        const char *slash = strrchr(info.dli_fname, '/');
        int len = slash ? (int)(slash - info.dli_fname) : 1;
        const char *dir = slash ? info.dli_fname : ".";
        static const char *const places[][2] = {{"", ""}, {"/..", ""}, {"/../", ORRERY_MODULE_LIBDIR}};
        for (size_t k = 0; k < sizeof places / sizeof places[0]; k++) {
            char at[ORR_PATH_MAX];
            if (snprintf(at, sizeof at, "%.*s%s%s", len, dir, places[k][0], places[k][1]) < (int)sizeof at &&
                try_dir(at, strlen(at)))
                return;
        }
    }
    if (try_dir(ORRERY_MODULE_DIR, strlen(ORRERY_MODULE_DIR)))
        return;
    if (!load_error[0])
        snprintf(load_error, sizeof load_error, MODULE_NAME " is neither beside liborrery nor in " ORRERY_MODULE_DIR);
}

/* The module, or NULL with err saying why it could not be loaded. */
static const orr_oiio_module *loaded(const char *path, orr_error *err)
{
    pthread_once(&load_once, load);
    if (!module)
        orr_fail(err, ORR_ERR_IO, "%s: OpenImageIO (orrery's module for TIFF, JPEG and other formats) cannot be "
                 "loaded: %s", path ? path : "(no name)", load_error);
    return module;
}

orr_status orr_write_oiio_named(const char *path, const float *pixels, int width, int height, int nchannels,
                                const char *const *channel_names, int bits, const orr_image_meta *meta,
                                orr_error *err)
{
    const orr_oiio_module *m = loaded(path, err);
    return m ? m->write(path, pixels, width, height, nchannels, channel_names, bits, meta, err) : ORR_ERR_IO;
}

orr_status orr_write_oiio(const char *path, const float *pixels, int width, int height, int nchannels, int bits,
                          const orr_image_meta *meta, orr_error *err)
{
    return orr_write_oiio_named(path, pixels, width, height, nchannels, NULL, bits, meta, err);
}

orr_status orr_read_oiio(const char *path, float **pixels, int *width, int *height, int *nchannels, orr_error *err)
{
    const orr_oiio_module *m = loaded(path, err);
    return m ? m->read(path, pixels, width, height, nchannels, err) : ORR_ERR_IO;
}

orr_status orr_read_oiio_planes(const char *path, orr_plane **planes, int *nplanes, orr_error *err)
{
    const orr_oiio_module *m = loaded(path, err);
    return m ? m->read_planes(path, planes, nplanes, err) : ORR_ERR_IO;
}

orr_status orr_oiio_get_attribute(const char *path, const char *name, char *buf, size_t size, orr_error *err)
{
    const orr_oiio_module *m = loaded(path, err);
    return m ? m->get_attribute(path, name, buf, size, err) : ORR_ERR_IO;
}
