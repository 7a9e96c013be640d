/* The end of a slab, on one rank or on one rank's part of the nodes, in
 * three vectorised loops instead of a dozen numpy calls and a PETSc
 * product (vstpetsc/line/native/closing.py): u += z_2, v = v1 z_1 + v2 z_2,
 * the elongations d of the node pairs, their envelopes lo <= d <= hi, the
 * energies of the state (kinetic 1/2 v^T M v, strain 1/2 sum k d^2) and
 * the running sum b += G z, G's three bands (bands.increment_bands,
 * difference form) laid out per dof row.
 *
 * The unknowns are mixed per node: z = (z_1, z_2) at x[2i], x[2i + 1].
 * On several ranks the nodes just beyond this rank's ends enter through
 * their z (z_left, z_right: the neighbours' values, one small scatter a
 * slab) and the u of the right one (u_right), whose pair with the last
 * owned node is this rank's last elongation.
 * u, v, d, lo, hi and b are the Python path's bit for bit (elementwise
 * IEEE operations in the same order, no fused multiply-add:
 * -ffp-contract=off); the energies equal it to rounding (on several ranks
 * they are partial sums, which nobody reads: the LineEnergyBook sums the
 * gathered state). */

#include <stddef.h>

typedef struct {
    int nodes;                 /* n, this rank's */
    const double *x;           /* slab unknowns (n, 2) */
    double *b;                 /* running right-hand side (n, 2) */
    const double *left, *diag, *right;   /* G's dof row r: on x[r - 2], x[r], x[r + 2] */
    double v1, v2;             /* v = v1 z_1 + v2 z_2 */
    double *u, *v;             /* displacements, end velocities (n) */
    double *d, *lo, *hi;       /* elongations and their envelopes (n - 1, n with u_right) */
    const double *m_diag;      /* mass matrix: diagonal (n) */
    const double *m_off;       /* and (i, i + 1) entries (n - 1) */
    const double *stiffness;   /* E A / h of the pairs (n - 1) */
    double kinetic, strain;    /* out */
    const double *z_left;      /* z of node n0 - 1 (2), NULL where the mesh begins */
    const double *z_right;     /* z of node n1 (2), NULL where the mesh ends */
    double *u_right;           /* u of node n1 (1), NULL where the mesh ends */
} Close;

/* b += G z on the dof rows r = lo .. hi - 1 in the difference form of
 * bands.increment_bands: L (x[r - 2] - x[r]) + D x[r] + R (x[r + 2] - x[r])
 * summed from 0, left to right, then added to b, as the Python path
 * (line/solver/slab_end.py) does on any number of ranks.  Every row here has
 * both neighbours on this rank, so the loop has no branch. */
static void band_rows(const Close *c, int lo, int hi)
{
    const double *restrict L = c->left, *restrict D = c->diag, *restrict R = c->right;
    const double *restrict x = c->x;
    double *restrict b = c->b;
#pragma omp simd
    for (int r = lo; r < hi; r++) {
        double s = 0.0;
        s += L[r] * (x[r - 2] - x[r]);
        s += D[r] * x[r];
        s += R[r] * (x[r + 2] - x[r]);
        b[r] += s;
    }
}

/* the same on the two rows of node i, its neighbours' z at zl and zr
 * (NULL: no neighbour on that side, its term left out) */
static void node_rows(const Close *c, int i, const double *zl, const double *zr)
{
    for (int a = 0; a < 2; a++) {
        int r = 2 * i + a;
        double s = 0.0;
        if (zl)
            s += c->left[r] * (zl[a] - c->x[r]);
        s += c->diag[r] * c->x[r];
        if (zr)
            s += c->right[r] * (zr[a] - c->x[r]);
        c->b[r] += s;
    }
}

/* u += z_2, v = v1 z_1 + v2 z_2; returns sum m_ii v_i^2 */
static double nodes_state(const Close *c)
{
    const double v1 = c->v1, v2 = c->v2;
    const double *restrict x = c->x, *restrict m = c->m_diag;
    double *restrict u = c->u, *restrict v = c->v;
    double diag = 0.0;
#pragma omp simd reduction(+:diag)
    for (int i = 0; i < c->nodes; i++) {
        double vi = x[2 * i] * v1 + x[2 * i + 1] * v2;
        u[i] += x[2 * i + 1];
        v[i] = vi;
        diag += m[i] * (vi * vi);
    }
    return diag;
}

/* the elongation d[p] = ur - ul and its envelope */
static inline void envelope(const Close *c, int p, double dp)
{
    c->d[p] = dp;
    c->lo[p] = dp < c->lo[p] ? dp : c->lo[p];
    c->hi[p] = dp > c->hi[p] ? dp : c->hi[p];
}

/* the elongations, their envelopes and the pairs' energy sums */
static void pairs_state(Close *c, double diag)
{
    const double *restrict u = c->u, *restrict v = c->v;
    const double *restrict m = c->m_off, *restrict k = c->stiffness;
    double *restrict d = c->d, *restrict lo = c->lo, *restrict hi = c->hi;
    double off = 0.0, strain = 0.0;
    int n = c->nodes;
#pragma omp simd reduction(+:off, strain)
    for (int p = 0; p < n - 1; p++) {
        double dp = u[p + 1] - u[p];
        d[p] = dp;
        lo[p] = dp < lo[p] ? dp : lo[p];
        hi[p] = dp > hi[p] ? dp : hi[p];
        off += m[p] * (v[p] * v[p + 1]);
        strain += k[p] * (dp * dp);
    }
    if (c->u_right != NULL) {           /* the pair with the next rank's first node */
        *c->u_right += c->z_right[1];
        envelope(c, n - 1, *c->u_right - u[n - 1]);
    }
    c->kinetic = 0.5 * diag + off;
    c->strain = 0.5 * strain;
}

void vst_close(Close *c)
{
    /* three loops, elementwise but for the energies' sums (in any order:
     * omp simd reductions), so that the compiler vectorises them; the
     * rows of the first and last node, whose neighbours may be another
     * rank's, apart */
    int n = c->nodes;
    if (n < 1)
        return;
    if (n == 1) {
        node_rows(c, 0, c->z_left, c->z_right);
    } else {
        node_rows(c, 0, c->z_left, c->x + 2);
        band_rows(c, 2, 2 * n - 2);
        node_rows(c, n - 1, c->x + 2 * n - 4, c->z_right);
    }
    pairs_state(c, nodes_state(c));
}
