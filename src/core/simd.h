/* Hot loops get a second copy compiled for AVX2 (eight floats an
 * instruction instead of SSE2's four), picked at run time for the CPU it
 * runs on (GCC's and Clang's function multi-versioning; the build stays
 * portable to any x86-64). AVX2 alone, without FMA: the clones do the same
 * IEEE operations on wider registers, so the results do not depend on the
 * machine. The wide clones add an AVX-512 copy (sixteen floats), only for
 * the loops it was measured to speed up: the sky maps' fused NGP gathers,
 * whose arctangents and square roots are most of their work (a 3600^2
 * dome master 4-11 % faster; the orthographic gather and the projection
 * batches were no faster). AVX-512F brings FMA instructions, but the build
 * passes -ffp-contract=off (CMakeLists.txt), so these clones too do the
 * same operations. Elsewhere the attributes are empty. */
#ifndef ORR_CORE_SIMD_H
#define ORR_CORE_SIMD_H

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__)) && !defined(ORR_NO_CLONES)
#define ORR_VECTOR_CLONES __attribute__((target_clones("avx2", "default")))
#define ORR_WIDE_VECTOR_CLONES __attribute__((target_clones("avx512f", "avx2", "default")))
#else
#define ORR_VECTOR_CLONES
#define ORR_WIDE_VECTOR_CLONES
#endif

/* For the body of a loop shared by such clones: inlined into each, so each
 * clone compiles it for its own target (left to itself, the compiler may
 * keep one out-of-line copy, built for the baseline). */
#if defined(__GNUC__) || defined(__clang__)
#define ORR_ALWAYS_INLINE inline __attribute__((always_inline))
#else
#define ORR_ALWAYS_INLINE inline
#endif

/* Asks for the cache line at p, to be written soon; nothing elsewhere. */
#if defined(__GNUC__) || defined(__clang__)
#define ORR_PREFETCH_FOR_WRITE(p) __builtin_prefetch((p), 1, 1)
#else
#define ORR_PREFETCH_FOR_WRITE(p) ((void)(p))
#endif

#endif
