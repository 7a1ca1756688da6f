/* Builds the kernel's separable expansion (orr_kernel.separable, see
 * splat/kernel.h) from the integrals of F over the n x n cells of width
 * 2 / n that tile [0, 2]^2 (row-major, symmetric). Called by
 * orr_kernel_init; fails only when out of memory or, which the tests
 * would show, when the eigenvectors do not converge. */
#ifndef ORR_SPLAT_KERNEL_SEPARABLE_H
#define ORR_SPLAT_KERNEL_SEPARABLE_H

#include "splat/kernel.h"

orr_status orr_kernel_fill_separable(orr_kernel *k, const double *cell, int n, orr_error *err);

#endif
