/* A kept row's copies out of the solver's arrays into the writer's
 * buffers (vstpetsc/native/rows.py) in one call: u, v and the stress of
 * every node, 24 bytes a node, written with non-temporal stores where
 * the processor has them (SSE2).  The buffers' rows are written once and
 * read only by the file's writer a block later, so caching them would
 * only evict the solver's data (and first read each line from memory).
 * Measured in the time loop at 10 000 nodes (docs/solver.md): 21-26 us,
 * against 35-42 us with ordinary stores and 37-40 us for numpy's copies. */

#include <stdint.h>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

typedef struct {
    const double *src;         /* the solver's values */
    const double *factor;      /* NULL: a copy; else dst = src * factor */
    double *dst;               /* row 0 of the bound buffer */
    long n;                    /* values a row */
    long stride;               /* doubles from a row to the next */
} Job;

static void copy_row(const Job *j, double *dst)
{
    const double *src = j->src, *f = j->factor;
    long i = 0, n = j->n;
#if defined(__SSE2__)
    /* one scalar value first when dst is not 16-byte aligned */
    if (n > 0 && ((uintptr_t)dst & 15)) {
        dst[0] = f ? src[0] * f[0] : src[0];
        i = 1;
    }
    if (f == NULL) {
        for (; i + 1 < n; i += 2)
            _mm_stream_pd(dst + i, _mm_loadu_pd(src + i));
    } else {
        for (; i + 1 < n; i += 2)
            _mm_stream_pd(dst + i, _mm_mul_pd(_mm_loadu_pd(src + i), _mm_loadu_pd(f + i)));
    }
#endif
    for (; i < n; i++)
        dst[i] = f ? src[i] * f[i] : src[i];
}

/* row ``row`` of every job's buffer */
void vst_rows_copy(const Job *jobs, int njobs, long row)
{
    for (int j = 0; j < njobs; j++)
        copy_row(&jobs[j], jobs[j].dst + row * jobs[j].stride);
#if defined(__SSE2__)
    _mm_sfence();      /* the stores are visible before the buffers are read */
#endif
}
