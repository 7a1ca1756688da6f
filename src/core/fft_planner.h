/* FFTW's planner, shared by every FFT user in the library (the PSF
 * convolution in post/, the particle-mesh code in source/): one lock around
 * planning and the wisdom files that make MEASURE plans repeatable. */
#ifndef ORR_CORE_FFT_PLANNER_H
#define ORR_CORE_FFT_PLANNER_H

#include "core/error.h"

/* FFTW wisdom: what MEASURE planning learnt, saved to a file and loaded in
 * a later run (or on every MPI rank), so MEASURE plans are made at once and
 * are the same plans every time, hence the same bits. Both take the planner
 * lock. Load fails with ORR_ERR_IO for a missing file and ORR_ERR_FORMAT for
 * one FFTW does not accept (e.g. from another FFTW build). */
orr_status orr_fft_wisdom_save(const char *path, orr_error *err);
orr_status orr_fft_wisdom_load(const char *path, orr_error *err);

/* FFTW planning (creating and destroying plans) must not run concurrently
 * with itself anywhere in the process; orrery's own FFT users call these
 * around it. The first call also initialises FFTW's threads. Returns
 * ORR_ERR_INTERNAL when FFTW's threads cannot start. */
orr_status orr_fft_planner_lock(orr_error *err);
void orr_fft_planner_unlock(void);

#endif
