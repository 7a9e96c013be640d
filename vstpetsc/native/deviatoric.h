/* The plane-strain MKZ-Masing slab integrals (deviatoric.c). */
#ifndef VST_DEVIATORIC_H
#define VST_DEVIATORIC_H

typedef struct {
    long n;                                   /* material points */
    int depth;                                /* stack depth (masing.DEPTH) */
    double dt;
    const double *G, *gref, *beta, *s, *K;    /* (n) */
    const double *xg, *wg;                    /* Gauss points and weights on [0, 1] */
    /* the slab start: strains, stress deviators (n, 3), the stacks
     * (n, depth, 3) and depths (n), the heading n0 (n, 3), virgin (n) */
    const double *eps, *dev, *sc, *ss;
    const long *k;
    const double *n0;
    const unsigned char *virgin;
    const double *D1, *D2;                    /* (n, 3) */
    /* frozen decisions (fturned NULL: the rules decide) */
    const unsigned char *fturned, *freverses;
    const double *fcut;
    const long *fkc, *fk;                     /* (n), (n, 2, 3) */
    double *Q, *dQ;                           /* (n, 2, 3), (n, 2, 3, 2, 3) or NULL */
    /* the decisions taken and the turn point's strain and stress deviator */
    unsigned char *turned, *reverses;
    double *cut;
    long *kc, *kk;
    double *eps_c, *s_c;
} DeviatoricSlab;

int vst_deviatoric_slab(DeviatoricSlab *m);

#endif
