/* bench_time.h -- the C micro-benchmarks' clock and median (benchmarks/c/element_kernel.c,
 * benchmarks/c/planar_kernels.c). Include it first: it asks for POSIX's clock_gettime. */
#ifndef PHM_BENCH_TIME_H
#define PHM_BENCH_TIME_H

#ifndef _POSIX_C_SOURCE
#define _POSIX_C_SOURCE 199309L /* clock_gettime */
#endif
#include <stdlib.h>
#include <time.h>

/* The calling thread's CPU time [s]. */
static inline double bench_now(void) {
  struct timespec ts;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

static inline int bench_cmp(const void *a, const void *b) {
  double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

/* The median of t[0..n) (t is sorted). */
static inline double bench_median(double *t, int n) {
  qsort(t, (size_t)n, sizeof t[0], bench_cmp);
  return t[n / 2];
}

#endif
