#include "core/fft_planner.h"

#include <fftw3.h>
#include <pthread.h>
#include <stdio.h>

static pthread_mutex_t planner_mutex = PTHREAD_MUTEX_INITIALIZER;
static pthread_once_t threads_once = PTHREAD_ONCE_INIT;
static int threads_ok;

/* FFTW's threads must be initialised once before any threaded plan. The
 * planner is also made thread-safe in FFTW itself, for FFTW users elsewhere
 * in the process that do not know about our lock. */
static void init_fftw_threads(void)
{
    threads_ok = fftwf_init_threads() != 0;
    if (threads_ok)
        fftwf_make_planner_thread_safe();
}

orr_status orr_fft_planner_lock(orr_error *err)
{
    pthread_once(&threads_once, init_fftw_threads);
    if (!threads_ok)
        return orr_fail(err, ORR_ERR_INTERNAL, "FFTW could not initialise its threads");
    pthread_mutex_lock(&planner_mutex);
    return ORR_OK;
}

void orr_fft_planner_unlock(void)
{
    pthread_mutex_unlock(&planner_mutex);
}

orr_status orr_fft_wisdom_save(const char *path, orr_error *err)
{
    orr_status st = orr_fft_planner_lock(err);
    if (st)
        return st;
    int ok = fftwf_export_wisdom_to_filename(path);
    orr_fft_planner_unlock();
    return ok ? ORR_OK : orr_fail(err, ORR_ERR_IO, "%s: cannot write FFTW wisdom", path);
}

orr_status orr_fft_wisdom_load(const char *path, orr_error *err)
{
    FILE *f = fopen(path, "r");
    if (!f)
        return orr_fail(err, ORR_ERR_IO, "%s: cannot open FFTW wisdom", path);
    orr_status st = orr_fft_planner_lock(err);
    if (st) {
        fclose(f);
        return st;
    }
    int ok = fftwf_import_wisdom_from_file(f);
    orr_fft_planner_unlock();
    fclose(f);
    return ok ? ORR_OK : orr_fail(err, ORR_ERR_FORMAT, "%s: not FFTW single-precision wisdom", path);
}
