/* The OpenImageIO module's table (liborrery-oiio.so, built from oiio.cpp):
 * encode/oiio_load.c loads the module on first use and calls these, which
 * are the functions of encode/oiio.h. */
#ifndef ORR_ENCODE_OIIO_MODULE_H
#define ORR_ENCODE_OIIO_MODULE_H

#include <stddef.h>

#include "core/error.h"
#include "core/plane.h"
#include "encode/image_out.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Changes whenever the table does: a module of another build is refused. */
#define ORR_OIIO_MODULE_VERSION 1

typedef struct orr_oiio_module {
    int version;
    orr_status (*write)(const char *path, const float *pixels, int width, int height, int nchannels,
                        const char *const *channel_names, int bits, const orr_image_meta *meta, orr_error *err);
    orr_status (*read)(const char *path, float **pixels, int *width, int *height, int *nchannels, orr_error *err);
    orr_status (*read_planes)(const char *path, orr_plane **planes, int *nplanes, orr_error *err);
    orr_status (*get_attribute)(const char *path, const char *name, char *buf, size_t size, orr_error *err);
} orr_oiio_module;

/* The module's entry point, found with dlsym. */
const orr_oiio_module *orr_oiio_module_entry(void);

#ifdef __cplusplus
}
#endif

#endif
