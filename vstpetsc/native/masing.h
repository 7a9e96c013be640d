/* The hysteretic soil's slab (masing.c) and its Newton (soil_newton.c). */
#ifndef VST_MASING_H
#define VST_MASING_H

typedef struct {
    long ne;            /* elements */
    int depth;          /* stack depth (masing.DEPTH) */
    double dt;
    const double *G, *gref, *beta, *s, *area, *keh;
    const double *xg, *wg;                    /* Gauss points and weights on [0, 1] */
    /* the state at the slab start */
    const double *gamma, *tau, *dir, *sg, *st;
    const long *k;
    const double *D;                          /* (ne, 2) */
    double *Q, *dQ;                           /* (ne, 2), (ne, 2, 2) or NULL */
    /* the state at the slab end (finish), or NULL */
    double *gamma1, *tau1, *dir1, *sg1, *st1;
    long *k1;
    /* the residual in the solver's unknowns (vst_masing_residual) */
    long n;                                   /* the soil's nodes */
    const long *left;                         /* each element's left node among them */
    const double *scale;                      /* dt / h */
    const double *free;                       /* 1 where the node's rows take forces */
    const double *V, *W;                      /* 2 x 2, row major */
    const double *values;                     /* (n, 2): the unknowns z at the nodes */
    double *rows;                             /* (n, 2): W r, free nodes only */
    double *blocks;                           /* (ne, 2, 2): W (dt/h) dQ V, or NULL */
    /* the tangent's matrix data (block CSR, this rank's rows): base plus
     * the blocks at each element's four slots (-1: another rank's row),
     * in the order ll, lr, rr, rl, times sign x free (pdata NULL: none) */
    const double *pbase;
    double *pdata;
    long nb;                                  /* blocks in pdata */
    const long *slots;                        /* (4, ne) */
    const double *pcoef;                      /* (4, ne) */
} MasingSlab;

void vst_masing_residual(MasingSlab *m);

#endif
