/* The contact laws' terms at their coordinates y, for every compiled
 * Newton that solves them: a penalty pair's (PenaltyContact.force, pair.h)
 * and the Coulomb friction of a pair (CoulombFriction.force, coulomb.h),
 * which reads its pair's normal force of the same evaluation
 * (PenaltyContact.normal_force).  The operations of the Python laws in
 * their order.  penalty_newton.c (the laws' own Newton) and hosted_laws.h
 * (the laws inside the soil's Newton) both call law_forces(). */
#ifndef VST_LAW_FORCES_H
#define VST_LAW_FORCES_H

#include <string.h>

#include "coulomb.h"
#include "pair.h"

#define FRICTION_INPUTS 5      /* a friction law's mu, k_t, wall sign, wall v^1, v^2 */
#define FRICTION_OUTPUTS 10    /* a FrictionSlab's numbers */

typedef struct {
    int laws;                  /* L: 2L coordinates y */
    double dt;
    const double *gn;          /* (L) the pairs' gaps at t^n */
    const double *w;           /* (L) the pairs' penalties */
    const int *power;          /* (L) 1: the "power" weight T_a, 0: the seed's I_a */
    double *out;               /* out: (6L) (f1, f2, t11, t12, t21, t22) */
    double *integrals;         /* out: (6L) a pair's (G1, G2, W11, W12, W21, W22) */
    int *hit;                  /* out: (L) whether each law acts */
    const int *kind;           /* (L) 0 a penalty pair, 1 the friction of pair partner[j]; NULL: pairs only */
    const int *partner;        /* (L) a friction law's pair (before it) */
    const double *friction;    /* (5L) a friction law's FRICTION_INPUTS */
    const double *stretch;     /* (L) a friction law's stretch at t^n */
    double *fslab;             /* out: (10L) a friction law's FrictionSlab */
    int unsettled;             /* out: a friction law's switches did not settle */
} LawForces;

static inline int law_is_friction(const LawForces *c, int j)
{
    return c->kind != NULL && c->kind[j] != 0;
}

/* penalty pair j at y: whether it acts, and then its integrals and terms */
static inline int law_pair_force(LawForces *c, int j, const double *y)
{
    double *G = c->integrals + 6 * j, *o = c->out + 6 * j, w = c->w[j];
    if (!pair_integrals(c->gn[j], y[2 * j], y[2 * j + 1], c->dt, c->power[j], G))
        return 0;
    o[0] = -w * G[0]; o[1] = -w * G[1];
    o[2] = w * G[2]; o[3] = w * G[3]; o[4] = w * G[4]; o[5] = w * G[5];
    return 1;
}

/* friction law j at y, its pair's normal force of this evaluation:
 * whether it acts (its pair does), then its terms and its FrictionSlab */
static inline int law_friction_force(LawForces *c, int j, const double *y)
{
    int p = c->partner[j], count = 1;
    double normal[3], pieces[6] = {0.0, 1.0}, a[3];
    if (!c->hit[p])
        return 0;
    if (c->power[p]) {         /* k max(0, -g) on the gap's active pieces */
        gap_coefficients(c->gn[p], y[2 * p], y[2 * p + 1], c->dt, a);
        penalty_normal(a, c->w[p], normal);
        count = active_intervals(a, pieces);
    } else {                   /* the seed's slab mean J / dt on the whole slab */
        const double *G = c->integrals + 6 * p;
        normal[0] = -c->w[p] * (G[0] + G[1]) / c->dt;
        normal[1] = normal[2] = 0.0;
    }
    const double *in = c->friction + FRICTION_INPUTS * j;
    double wall = in[2];       /* the wall as a node of the pair: +1, -1 or 0 */
    FrictionSlab slab;
    if (coulomb_friction_integrals(c->stretch[j], -(y[2 * j] + wall * in[3]),
                                   -(y[2 * j + 1] + wall * in[4]), c->dt, in[1], in[0],
                                   normal, pieces, count, &slab)) {
        c->unsettled = 1;
        return 0;
    }
    double *out = c->out + 6 * j;
    memcpy(c->fslab + FRICTION_OUTPUTS * j, &slab, sizeof slab);
    out[0] = slab.f1; out[1] = slab.f2;
    out[2] = -slab.d11; out[3] = -slab.d12; out[4] = -slab.d21; out[5] = -slab.d22;
    return 1;
}

/* every law at y (a pair before its friction): hit, out; whether any acts */
static inline int law_forces(LawForces *c, const double *y)
{
    int any = 0;
    for (int j = 0; j < c->laws; j++) {
        c->hit[j] = law_is_friction(c, j) ? law_friction_force(c, j, y)
            : law_pair_force(c, j, y);
        any |= c->hit[j];
    }
    return any;
}

#endif
