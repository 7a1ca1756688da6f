/* Loading numbers from file bytes in either byte order, for the binary
 * snapshot readers. `swap` means the file's byte order is the reverse of the
 * host's. memcpy keeps the loads free of alignment and aliasing problems;
 * the reinterpretations (two's complement, IEEE 754) are the formats'. */
#ifndef ORR_CORE_BYTES_H
#define ORR_CORE_BYTES_H

#include <stdint.h>
#include <string.h>

static inline int orr_host_big_endian(void)
{
    const uint16_t one = 1;
    unsigned char first;
    memcpy(&first, &one, 1);
    return first == 0;
}

static inline uint32_t orr_load_u32(const unsigned char *p, int swap)
{
    uint32_t v;
    memcpy(&v, p, 4);
    return swap ? (v >> 24) | ((v >> 8) & 0xff00u) | ((v << 8) & 0xff0000u) | (v << 24) : v;
}

static inline uint64_t orr_load_u64(const unsigned char *p, int swap)
{
    uint64_t a = orr_load_u32(p, swap), b = orr_load_u32(p + 4, swap);
    /* Swapped, the first four bytes are the low half's mirror image. */
    uint64_t first_is_low = orr_host_big_endian() ? swap : !swap;
    return first_is_low ? a | b << 32 : a << 32 | b;
}

static inline int32_t orr_load_i32(const unsigned char *p, int swap)
{
    uint32_t u = orr_load_u32(p, swap);
    int32_t v;
    memcpy(&v, &u, 4);
    return v;
}

static inline float orr_load_f32(const unsigned char *p, int swap)
{
    uint32_t u = orr_load_u32(p, swap);
    float v;
    memcpy(&v, &u, 4);
    return v;
}

static inline double orr_load_f64(const unsigned char *p, int swap)
{
    uint64_t u = orr_load_u64(p, swap);
    double v;
    memcpy(&v, &u, 8);
    return v;
}

#endif
