/* vstpetsc.kernels.gap's tests and roots of a quadratic on [0, 1], with the
 * same floating-point operations as the Python.  Shared by
 * penalty_newton.c and smith_slab.c. */
#ifndef VST_GAP_H
#define VST_GAP_H

#include <math.h>

static inline int closed_somewhere(double a0, double a1, double a2)
{
    if (a0 < 0.0 || a0 + a1 + a2 < 0.0)
        return 1;
    if (a2 > 0.0) {
        double t = -a1 / (2.0 * a2);
        return 0.0 < t && t < 1.0 && a0 + t * (a1 + t * a2) < 0.0;
    }
    return 0;
}

/* roots of a0 + a1 t + a2 t^2 strictly inside (0, 1), sorted: their count */
static inline int roots01(double a0, double a1, double a2, double *r)
{
    double c[2];
    int n = 0, k = 0;
    if (a2 != 0.0) {
        double disc = a1 * a1 - 4.0 * a2 * a0;
        if (disc < 0.0)
            return 0;
        double q = -0.5 * (a1 + copysign(sqrt(disc), a1));
        if (q == 0.0)
            return 0;
        double r1 = q / a2, r2 = a0 / q;
        /* Python's sorted((r1, r2)): swap only when r2 < r1 */
        if (r2 < r1) { c[0] = r2; c[1] = r1; } else { c[0] = r1; c[1] = r2; }
        n = 2;
    } else if (a1 != 0.0) {
        c[0] = -a0 / a1;
        n = 1;
    }
    for (int i = 0; i < n; i++)
        if (0.0 < c[i] && c[i] < 1.0)
            r[k++] = c[i];
    return k;
}

/* Python's max(map(abs, a)): the first of the largest */
static inline double max_abs(const double *a, int n)
{
    double m = fabs(a[0]);
    for (int i = 1; i < n; i++) {
        double x = fabs(a[i]);
        if (x > m)
            m = x;
    }
    return m;
}

#endif
