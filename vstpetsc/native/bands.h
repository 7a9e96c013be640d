/* 2 x 2 block tridiagonal bands (N, 3, 2, 2), row major: [i][0] couples
 * node i to i - 1, [1] to itself, [2] to i + 1; their LU by the block
 * Thomas algorithm (natural order: a block tridiagonal matrix fills
 * nothing in).  Shared by soil_newton.c and smith_slab.c. */
#ifndef VST_BANDS_H
#define VST_BANDS_H

static inline void inv2(const double *a, double *out)
{
    double det = a[0] * a[3] - a[1] * a[2];
    out[0] = a[3] / det;
    out[1] = -a[1] / det;
    out[2] = -a[2] / det;
    out[3] = a[0] / det;
}

static inline void mul2(const double *a, const double *b, double *out)     /* out = a b */
{
    double o0 = a[0] * b[0] + a[1] * b[2], o1 = a[0] * b[1] + a[1] * b[3];
    double o2 = a[2] * b[0] + a[3] * b[2], o3 = a[2] * b[1] + a[3] * b[3];
    out[0] = o0, out[1] = o1, out[2] = o2, out[3] = o3;
}

static inline void mv2(const double *a, const double *x, double *out)      /* out = a x */
{
    double o0 = a[0] * x[0] + a[1] * x[1], o1 = a[2] * x[0] + a[3] * x[1];
    out[0] = o0, out[1] = o1;
}

/* block Thomas factors of the bands B: Minv_i = (D_i - L_i Cp_{i-1})^{-1},
 * Cp_i = Minv_i U_i */
static inline void bands_factor(long N, const double *B, double *Minv, double *Cp)
{
    for (long i = 0; i < N; i++) {
        const double *L = B + 12 * i, *D = L + 4, *U = L + 8;
        double M[4] = {D[0], D[1], D[2], D[3]}, t[4];
        if (i > 0) {
            mul2(L, Cp + 4 * (i - 1), t);
            for (int k = 0; k < 4; k++)
                M[k] -= t[k];
        }
        inv2(M, Minv + 4 * i);
        mul2(Minv + 4 * i, U, Cp + 4 * i);
    }
}

/* y = B^{-1} r from the factors */
static inline void bands_solve(long N, const double *B, const double *Minv, const double *Cp,
                               const double *r, double *y)
{
    for (long i = 0; i < N; i++) {
        double t[2] = {r[2 * i], r[2 * i + 1]}, u[2];
        if (i > 0) {
            mv2(B + 12 * i, y + 2 * (i - 1), u);
            t[0] -= u[0], t[1] -= u[1];
        }
        mv2(Minv + 4 * i, t, y + 2 * i);
    }
    for (long i = N - 2; i >= 0; i--) {
        double u[2];
        mv2(Cp + 4 * i, y + 2 * (i + 1), u);
        y[2 * i] -= u[0], y[2 * i + 1] -= u[1];
    }
}

#endif
