/* The end of a slab on one rank, in two passes over the nodes instead of
 * a dozen numpy calls (vstpetsc/native/closing.py):
 *
 *   vst_close_state: u += z_2, v = v1 . z, the elongations d of the node
 *       pairs, their envelopes lo <= d <= hi and the energies of the state
 *       (kinetic 1/2 v^T M v, strain 1/2 sum k d^2);
 *   vst_band_add:    b += G z, G of three entries a row (slab.increment_bands).
 *
 * The unknowns are mixed per node: z = (z_1, z_2) at x[2i], x[2i + 1].
 * u, v, d, lo, hi and b are the Python path's bit for bit; the
 * energies equal it to rounding (numpy's dot sums in blocks). */

typedef struct {
    int nodes;                 /* n */
    const double *x;           /* slab unknowns (n, 2) */
    double *b;                 /* running right-hand side (n, 2) */
    const double *band;        /* G's rows (n, 2, 3): columns i - 1, i, i + 1 */
    double v1, v2;             /* v = v1 z_1 + v2 z_2 */
    double *u, *v;             /* displacements, end velocities (n) */
    double *d, *lo, *hi;       /* elongations and their envelopes (n - 1) */
    const double *m_diag;      /* mass matrix: diagonal (n) */
    const double *m_off;       /* and (i, i + 1) entries (n - 1) */
    const double *stiffness;   /* E A / h of the pairs (n - 1) */
    double kinetic, strain;    /* out */
} Close;

void vst_close_state(Close *c)
{
    const double *x = c->x;
    double *u = c->u, *v = c->v, *d = c->d, *lo = c->lo, *hi = c->hi;
    double diag = 0.0, off = 0.0, strain = 0.0;
    double u_prev = 0.0, v_prev = 0.0;
    for (int i = 0; i < c->nodes; i++) {
        double ui = u[i] + x[2 * i + 1];
        double vi = x[2 * i] * c->v1 + x[2 * i + 1] * c->v2;
        u[i] = ui;
        v[i] = vi;
        diag += c->m_diag[i] * (vi * vi);
        if (i > 0) {
            double di = ui - u_prev;
            d[i - 1] = di;
            lo[i - 1] = di < lo[i - 1] ? di : lo[i - 1];
            hi[i - 1] = di > hi[i - 1] ? di : hi[i - 1];
            off += c->m_off[i - 1] * (v_prev * vi);
            strain += c->stiffness[i - 1] * (di * di);
        }
        u_prev = ui;
        v_prev = vi;
    }
    c->kinetic = 0.5 * diag + off;
    c->strain = 0.5 * strain;
}

/* one row's products, summed left to right from 0 (left, right: whether
 * the neighbours i - 1 and i + 1 exist) */
static double band_row(const double *row, const double *z, int left, int right)
{
    double s = 0.0;
    if (left)
        s += row[0] * z[-2];
    s += row[1] * z[0];
    if (right)
        s += row[2] * z[2];
    return s;
}

void vst_band_add(Close *c)
{
    /* the row's products summed first, then added to b: PETSc's order
     * (MatMultAdd of its AIJ and SELL formats), which the parallel path
     * keeps, so that one rank and several sum alike; the first and last
     * node apart, so that the loop between has no branch */
    const double *x = c->x, *a = c->band;
    double *b = c->b;
    int n = c->nodes;
    if (n < 1)
        return;
    for (int k = 0; k < 2; k++)
        b[k] += band_row(a + 3 * k, x + k, 0, n > 1);
    for (int i = 1; i < n - 1; i++) {
        const double *row = a + 6 * i, *z = x + 2 * i;
        double s0 = row[0] * z[-2], s1 = row[3] * z[-1];
        s0 += row[1] * z[0];
        s1 += row[4] * z[1];
        s0 += row[2] * z[2];
        s1 += row[5] * z[3];
        b[2 * i] += s0;
        b[2 * i + 1] += s1;
    }
    if (n > 1)
        for (int k = 0; k < 2; k++)
            b[2 * (n - 1) + k] += band_row(a + 6 * (n - 1) + 3 * k, x + 2 * (n - 1) + k, 1, 0);
}
