/* Fingerprints of bytes: FNV-1a, 64 bits (Fowler, Noll and Vo), for names,
 * settings and file identities. Not for security. */
#ifndef ORR_CORE_DIGEST_H
#define ORR_CORE_DIGEST_H

#include <stddef.h>
#include <stdint.h>

/* FNV-1a's 64-bit offset basis: the digest of nothing. */
#define ORR_DIGEST_START 0xcbf29ce484222325u

/* Continues digest h over n bytes of data. */
uint64_t orr_digest(uint64_t h, const void *data, size_t n);
/* ... over a string without its terminator. */
uint64_t orr_digest_text(uint64_t h, const char *text);

#endif
