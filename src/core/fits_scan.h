/* A look at a FITS file's headers with plain stdio, before cfitsio opens
 * it: cfitsio (4.2) crashes, with SIGFPE or SIGSEGV, on some damaged
 * tile-compressed headers while merely moving to their HDU, before a
 * reader could refuse them. orrery reads only uncompressed images (its own
 * planes, PSF files), so a tile-compressed HDU anywhere in the file is
 * refused here, naming it. */
#ifndef ORR_CORE_FITS_SCAN_H
#define ORR_CORE_FITS_SCAN_H

#include "core/error.h"

/* ORR_ERR_USAGE when path is not a regular file (a FIFO, which is not
 * waited on, a device such as /dev/zero, a folder); ORR_ERR_FORMAT naming
 * path and the HDU when a header says ZIMAGE = T;
 * ORR_OK otherwise, also for a file that cannot be opened or is not FITS
 * at all (cfitsio then says what is wrong with it). `what` names the file's
 * role in the message ("PSF", "raw planes"). */
orr_status orr_fits_refuse_compressed(const char *path, const char *what, orr_error *err);

#endif
