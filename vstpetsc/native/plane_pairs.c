/* The node pairs of plane-strain interfaces over one slab, all in one
 * call: per pair the 1-D penalty pair's exact integrals along its normal
 * (pair.h) and, with friction, the exact Coulomb slab integrals along its
 * tangent (coulomb.h), whose limit follows that normal force.  The same
 * operations per pair as vstpetsc.plane.pair_kernels.one_pair (the
 * 1-D laws' Python kernels), which the tests hold it to.
 *
 * Per pair p, y[4 p ..] = (d1, d2, q1, q2): the closing rates along the
 * normal and the tangential coordinate q = -s (s: the second side's
 * tangential velocity relative to the first) at the slab's two time
 * nodes.  out[OUT p ..] (OUT = 18):
 *   0-1   f_n = -w G_a             (the normal law's terms)
 *   2-5   df_n / dd (row-major)
 *   6-7   f_t = F_a                (friction's terms; dF/ds = -df/dq)
 *   8-11  df_t / dq (row-major)
 *   12    the slab's impulse -w (G_1 + G_2)
 *   13    the friction spring's stretch at the slab's end
 *   14    slip in the slab
 *   15    dissipated: dissipation + released
 *   16    F_1 + F_2
 *   17    1 when the normal law acted (the gap closed somewhere) */
#include "coulomb.h"
#include "pair.h"

#define OUT 18

typedef struct {
    int m, power;
    double dt;
    const double *gap, *y, *w, *kt, *mu, *stretch;
    double *out;
} PlanePairs;

static int one_pair(const PlanePairs *P, int p, double *o)
{
    const double *y = P->y + 4 * p;
    double G[6], a[3], normal[3], pieces[6];
    for (int i = 0; i < OUT; i++)
        o[i] = 0.0;
    o[13] = 0.0;
    if (!pair_integrals(P->gap[p], y[0], y[1], P->dt, P->power, G))
        return 0;
    double w = P->w[p];
    o[0] = -w * G[0]; o[1] = -w * G[1];
    o[2] = w * G[2]; o[3] = w * G[3]; o[4] = w * G[4]; o[5] = w * G[5];
    o[12] = -w * (G[0] + G[1]);
    o[17] = 1.0;
    if (P->kt[p] <= 0.0)
        return 0;
    int count;
    if (P->power) {
        gap_coefficients(P->gap[p], y[0], y[1], P->dt, a);
        penalty_normal(a, w, normal);
        count = active_intervals(a, pieces);
    } else {
        normal[0] = -w * (G[0] + G[1]) / P->dt;
        normal[1] = normal[2] = 0.0;
        pieces[0] = 0.0; pieces[1] = 1.0;
        count = 1;
    }
    FrictionSlab f;
    if (coulomb_friction_integrals(P->stretch[p], -y[2], -y[3], P->dt, P->kt[p], P->mu[p],
                                   normal, pieces, count, &f))
        return 1;
    o[6] = f.f1; o[7] = f.f2;
    o[8] = -f.d11; o[9] = -f.d12; o[10] = -f.d21; o[11] = -f.d22;
    o[13] = f.stretch;
    o[14] = f.slip;
    o[15] = f.dissipation + f.released;
    o[16] = f.f1 + f.f2;
    return 0;
}

/* 0, or 1 + the first pair whose friction switches did not settle */
int vst_plane_pairs(const PlanePairs *P)
{
    for (int p = 0; p < P->m; p++)
        if (one_pair(P, p, P->out + OUT * p))
            return 1 + p;
    return 0;
}
