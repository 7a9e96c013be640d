/* A sweep of a block-triangular solve in 4 x 4 node blocks
 * (vstpetsc/plane/solver/separated.py): for each block row i in the given
 * order, x_i <- D_i (x_i - sum_j B_ij x_j) over the row's off-diagonal
 * blocks B_ij, with D_i the inverse of its diagonal block.  Rows in
 * ascending order with L's blocks are the forward sweep, in descending
 * order with U's the backward one: the factors' entries are read once, 16
 * values to an index (PETSc's BAIJ solves do the same).  The blocks are
 * stored in the order the sweep takes them (row k of ptr and dinv is the
 * k-th row swept), so that both sweeps read memory forwards: read
 * backwards, the backward sweep took 4 times as long. */

void vst_block_sweep(long rows, int descending, const int *ptr, const int *col,
                     const double *off, const double *dinv, double *x)
{
    for (long k = 0; k < rows; k++) {
        long i = descending ? rows - 1 - k : k;
        double s0 = x[4 * i], s1 = x[4 * i + 1], s2 = x[4 * i + 2], s3 = x[4 * i + 3];
        for (int p = ptr[k]; p < ptr[k + 1]; p++) {
            const double *b = off + 16 * (long)p, *y = x + 4 * (long)col[p];
            s0 -= b[0] * y[0] + b[1] * y[1] + b[2] * y[2] + b[3] * y[3];
            s1 -= b[4] * y[0] + b[5] * y[1] + b[6] * y[2] + b[7] * y[3];
            s2 -= b[8] * y[0] + b[9] * y[1] + b[10] * y[2] + b[11] * y[3];
            s3 -= b[12] * y[0] + b[13] * y[1] + b[14] * y[2] + b[15] * y[3];
        }
        const double *d = dinv + 16 * k;
        x[4 * i] = d[0] * s0 + d[1] * s1 + d[2] * s2 + d[3] * s3;
        x[4 * i + 1] = d[4] * s0 + d[5] * s1 + d[6] * s2 + d[7] * s3;
        x[4 * i + 2] = d[8] * s0 + d[9] * s1 + d[10] * s2 + d[11] * s3;
        x[4 * i + 3] = d[12] * s0 + d[13] * s1 + d[14] * s2 + d[15] * s3;
    }
}

/* The same sweep for k right-hand sides at once (x: row-major, the k
 * values of an unknown together): the factors read once for all k (the
 * interfaces' coupling columns, four a pair, vstpetsc.plane.solver.separated). */
void vst_block_sweep_many(long rows, int descending, const int *ptr, const int *col,
                          const double *off, const double *dinv, double *x, long k)
{
    double s[4 * 64];
    for (long step = 0; step < rows; step++) {
        long i = descending ? rows - 1 - step : step;
        for (long c0 = 0; c0 < k; c0 += 64) {
            long m = k - c0 < 64 ? k - c0 : 64;
            for (int a = 0; a < 4; a++)
                for (long c = 0; c < m; c++) s[a * 64 + c] = x[(4 * i + a) * k + c0 + c];
            for (int p = ptr[step]; p < ptr[step + 1]; p++) {
                const double *b = off + 16 * (long)p, *y = x + 4 * (long)col[p] * k + c0;
                for (int a = 0; a < 4; a++)
                    for (long c = 0; c < m; c++)
                        s[a * 64 + c] -= b[4 * a] * y[c] + b[4 * a + 1] * y[k + c]
                                         + b[4 * a + 2] * y[2 * k + c] + b[4 * a + 3] * y[3 * k + c];
            }
            const double *d = dinv + 16 * step;
            for (int a = 0; a < 4; a++)
                for (long c = 0; c < m; c++)
                    x[(4 * i + a) * k + c0 + c] = d[4 * a] * s[c] + d[4 * a + 1] * s[64 + c]
                                                   + d[4 * a + 2] * s[128 + c] + d[4 * a + 3] * s[192 + c];
        }
    }
}
