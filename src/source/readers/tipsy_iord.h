/* Tipsy's auxiliary id array: ChaNGa and Gasoline write each particle's
 * permanent id (iOrder) beside the snapshot, as SNAPSHOT.iord, since the
 * Tipsy records have none. Without it the ids are file positions, which
 * change from snapshot to snapshot of a run that forms stars, so snapshots
 * interpolated in time would match the wrong particles.
 *
 * Two forms, told apart by the file's size:
 *   binary: a 32-bit count, then count ids of 32 (or 64) bits, big-endian
 *           (XDR, as ChaNGa writes) or little-endian, the count saying which;
 *   ASCII:  the count on the first line, then one id a line (Gasoline).
 * The count must be the snapshot's nbodies; ids must be integers, not
 * negative. Ids are read as the particles are, a chunk at a time: a binary
 * file by seeking, an ASCII one in order (a rewind reads it again). */
#ifndef ORR_SOURCE_TIPSY_IORD_H
#define ORR_SOURCE_TIPSY_IORD_H

#include <stdint.h>
#include <stdio.h>

#include "core/error.h"
#include "core/limits.h"

typedef struct orr_tipsy_iord {
    FILE *fp;
    char path[ORR_PATH_MAX];
    int binary;     /* 1: binary; 0: ASCII */
    int width;      /* binary: bytes an id, 4 or 8 */
    int swap;       /* binary: stored in the other byte order than the host's */
    int64_t next;   /* ASCII: index of the id the file is positioned at */
    long line;      /* ASCII: the line that id is on */
} orr_tipsy_iord;

/* Opens SNAPSHOT.iord when it exists (*found = 1) and checks its form and
 * count against nbodies; *found = 0 and ORR_OK when there is none. */
orr_status orr_tipsy_iord_open(orr_tipsy_iord *a, const char *snapshot, int64_t nbodies, int *found,
                               orr_error *err);

/* The ids of particles first .. first + n - 1 (file order) into out. */
orr_status orr_tipsy_iord_read(orr_tipsy_iord *a, int64_t first, size_t n, uint64_t *out, orr_error *err);

void orr_tipsy_iord_close(orr_tipsy_iord *a);

#endif
