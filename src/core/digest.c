#include "core/digest.h"

#include <string.h>

uint64_t orr_digest(uint64_t h, const void *data, size_t n)
{
    const unsigned char *p = data;
    for (size_t i = 0; i < n; i++)
        h = (h ^ p[i]) * 0x100000001b3u; /* FNV-1a's 64-bit prime */
    return h;
}

uint64_t orr_digest_text(uint64_t h, const char *text) { return orr_digest(h, text, strlen(text)); }
