#include <stdlib.h>

/* A sweep of a block-triangular solve by columns of 4 x 4 node blocks
 * (vstpetsc/plane/solver/separated.py): for each block column j in the
 * given order, x_j <- D_j x_j (D_j the inverse of its diagonal block, or
 * the identity), then x_i <- x_i - B_ij x_j for each of the column's
 * other blocks B_ij.  Columns in ascending order with L's blocks are the
 * forward sweep, in descending order with U's the backward one.  Columns
 * read the factors as SuperLU gives them (no conversion to rows), 16
 * values to an index, in the order the sweep takes them (column k of ptr
 * and dinv is the k-th swept), so that memory is read forwards (read
 * backwards, a sweep took 4 times as long).  A row's updates arrive in the
 * order of its columns' steps: forwards, in ascending columns, the same
 * operations as a sweep by rows.  Measured on half the 1 m rockfill dam's
 * slab matrix (190 000 blocks), min of 60: forwards 1.25 ms by columns
 * against 1.13 by rows, backwards 0.97 against 0.96; by rows each factor
 * would first be converted (0.1 s). */

static void column(const int *row, const double *off, int first, int last, const double *d,
                   double *x, long j)
{
    double x0 = x[4 * j], x1 = x[4 * j + 1], x2 = x[4 * j + 2], x3 = x[4 * j + 3];
    double y0 = d[0] * x0 + d[1] * x1 + d[2] * x2 + d[3] * x3;
    double y1 = d[4] * x0 + d[5] * x1 + d[6] * x2 + d[7] * x3;
    double y2 = d[8] * x0 + d[9] * x1 + d[10] * x2 + d[11] * x3;
    double y3 = d[12] * x0 + d[13] * x1 + d[14] * x2 + d[15] * x3;
    x[4 * j] = y0; x[4 * j + 1] = y1; x[4 * j + 2] = y2; x[4 * j + 3] = y3;
    for (int p = first; p < last; p++) {
        const double *b = off + 16 * (long)p;
        double *t = x + 4 * (long)row[p];
        t[0] -= b[0] * y0 + b[1] * y1 + b[2] * y2 + b[3] * y3;
        t[1] -= b[4] * y0 + b[5] * y1 + b[6] * y2 + b[7] * y3;
        t[2] -= b[8] * y0 + b[9] * y1 + b[10] * y2 + b[11] * y3;
        t[3] -= b[12] * y0 + b[13] * y1 + b[14] * y2 + b[15] * y3;
    }
}

void vst_column_sweep(long columns, int descending, const int *ptr, const int *row,
                     const double *off, const double *dinv, double *x)
{
    for (long k = 0; k < columns; k++)
        column(row, off, ptr[k], ptr[k + 1], dinv + 16 * k, x,
               descending ? columns - 1 - k : k);
}

/* The same sweep for m right-hand sides at once (x: row-major, the m
 * values of an unknown together): the factors read once for all (the
 * interfaces' coupling columns); each right-hand side the same operations,
 * in the same order, as its sweep alone.  On half the 1 m rockfill dam's
 * slab matrix, two ranks, ms a column (a whole solve): 2.9-3.9 alone, 2.5-2.6 for
 * 4 at once, 1.8 for 8, 1.3 for 16, 1.0 for 128 (the arithmetic, not the
 * factors' reading, bounds it: an unrolled kernel for four columns took
 * 1.9). */
void vst_column_sweep_many(long columns, int descending, const int *ptr, const int *row,
                           const double *off, const double *dinv, double *x, long m)
{
    for (long k = 0; k < columns; k++) {
        long j = descending ? columns - 1 - k : k;
        const double *d = dinv + 16 * k;
        for (long c = 0; c < m; c++) {
            double x0 = x[4 * j * m + c], x1 = x[(4 * j + 1) * m + c];
            double x2 = x[(4 * j + 2) * m + c], x3 = x[(4 * j + 3) * m + c];
            x[4 * j * m + c] = d[0] * x0 + d[1] * x1 + d[2] * x2 + d[3] * x3;
            x[(4 * j + 1) * m + c] = d[4] * x0 + d[5] * x1 + d[6] * x2 + d[7] * x3;
            x[(4 * j + 2) * m + c] = d[8] * x0 + d[9] * x1 + d[10] * x2 + d[11] * x3;
            x[(4 * j + 3) * m + c] = d[12] * x0 + d[13] * x1 + d[14] * x2 + d[15] * x3;
        }
        const double *y = x + 4 * j * m;
        for (int p = ptr[k]; p < ptr[k + 1]; p++) {
            const double *b = off + 16 * (long)p;
            double *t = x + 4 * (long)row[p] * m;
            for (int a = 0; a < 4; a++)
                for (long c = 0; c < m; c++)
                    t[a * m + c] -= b[4 * a] * y[c] + b[4 * a + 1] * y[m + c]
                                    + b[4 * a + 2] * y[2 * m + c] + b[4 * a + 3] * y[3 * m + c];
        }
    }
}

/* The blocks a sweep reads, gathered from a CSC factor T (SuperLU's L or
 * U, scalar entries) in one pass over it: block column J < count, its
 * blocks of block row I < limit.  Two calls: first with blocks == NULL to
 * count each swept column's blocks (ptr[k + 1] = its count, k = J or
 * count - 1 - J when descending), then, ptr made cumulative by the
 * caller, to fill rows[], blocks[] (16 a block, row-major: T[4I + a,
 * 4J + c] at 16 p + 4 a + c) and diag[] (16 for each swept column: its
 * block (J, J) if J < limit, else left as given) in sweep order, a
 * column's blocks by ascending block row (as scipy's sorted blocks were:
 * unsorted, the backward sweep's scattered writes took 20 % longer).
 * slot[] (nodes entries, all -1 on entry and on return) keeps where a
 * block row went within the current column.  Replaces scipy's CSR
 * transpose, conversion to 4 x 4 blocks and sort (0.26-0.29 s a rank on
 * the 1 m rockfill dam's slab matrix; this, 0.05 s). */
static int ascending(const void *a, const void *b)
{
    int x = *(const int *)a, y = *(const int *)b;
    return (x > y) - (x < y);
}

void vst_block_columns(long count, long limit, int descending, const int *indptr,
                       const int *indices, const double *data, int *slot, int *ptr,
                       int *rows, double *blocks, double *diag)
{
    for (long J = 0; J < count; J++) {
        long k = descending ? count - 1 - J : J;
        int used = 0, at = blocks ? ptr[k] : 0;
        const int first = indptr[4 * J], last = indptr[4 * J + 4];
        for (int p = first; p < last; p++) {      /* the column's block rows */
            int I = indices[p] / 4;
            if (I < limit && I != J && slot[I] < 0) {
                slot[I] = used;
                if (blocks)
                    rows[at + used] = I;
                used++;
            }
        }
        if (!blocks) {
            ptr[k + 1] = used;
        } else {
            qsort(rows + at, used, sizeof(int), ascending);
            for (int q = 0; q < used; q++)
                slot[rows[at + q]] = q;
            for (long q = 16 * (long)at; q < 16 * (long)(at + used); q++)
                blocks[q] = 0.0;
            for (int c = 0; c < 4; c++)
                for (int p = indptr[4 * J + c]; p < indptr[4 * J + c + 1]; p++) {
                    int I = indices[p] / 4, a = indices[p] % 4;
                    if (I == J && I < limit)
                        diag[16 * k + 4 * a + c] = data[p];
                    else if (I < limit)
                        blocks[16 * (long)(at + slot[I]) + 4 * a + c] = data[p];
                }
        }
        for (int p = first; p < last; p++)        /* the slots back to -1 */
            if (indices[p] / 4 < limit)
                slot[indices[p] / 4] = -1;
    }
}

/* x -= sum_i w[i] Z[row[i]] (Z: rows of n values): the pairs' correction
 * A_c^-1 E (e - e0) from the kept coupling columns (pair_newton.py), each
 * row read once, subtracted in the order given, four rows in one pass
 * over x (the same operations as one row at a time).  numpy's w @ Z[rows]
 * first copied the rows: 100 rows of 26 000, one thread, 2.0-3.8 ms
 * against 1.6-1.9 for one row at a time. */
void vst_rows_axpy(long k, const long *row, const double *w, const double *Z, long n,
                   double *x)
{
    long i = 0;
    for (; i + 4 <= k; i += 4) {
        const double *z0 = Z + row[i] * n, *z1 = Z + row[i + 1] * n;
        const double *z2 = Z + row[i + 2] * n, *z3 = Z + row[i + 3] * n;
        const double a0 = w[i], a1 = w[i + 1], a2 = w[i + 2], a3 = w[i + 3];
#pragma omp simd
        for (long j = 0; j < n; j++) {
            double t = x[j];
            t -= a0 * z0[j];
            t -= a1 * z1[j];
            t -= a2 * z2[j];
            t -= a3 * z3[j];
            x[j] = t;
        }
    }
    for (; i < k; i++) {
        const double *z = Z + row[i] * n;
        const double a = w[i];
#pragma omp simd
        for (long j = 0; j < n; j++)
            x[j] -= a * z[j];
    }
}
