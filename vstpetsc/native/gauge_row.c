/* The gauges' row of a slab on one rank in one call (line/native/gauge_row.py): the
 * operations of vstpetsc.line.gauges.Gauges.fill on u and v^2 = z V1 read
 * straight from the solver's arrays, then the writer's column order. */

typedef struct {
    long channels;
    const long *left, *right;      /* each channel's element's nodes */
    const double *w, *factor, *inv_h;
    const double *u, *z;           /* the solver's u (a node) and z (2 a node) */
    const double *V1;              /* v^2 = z0 V1[0] + z1 V1[1] */
    const long *order;             /* the writer's column k holds values[order[k]] */
    double *values;                /* (4 channels): all u, all v, all stress, all strain */
} GaugeRow;

void vst_gauge_row(const GaugeRow *g, double *slot)
{
    long C = g->channels;
    for (long c = 0; c < C; c++) {
        long l = g->left[c], r = g->right[c];
        double w = g->w[c];
        double vl = g->z[2 * l] * g->V1[0] + g->z[2 * l + 1] * g->V1[1];
        double vr = g->z[2 * r] * g->V1[0] + g->z[2 * r + 1] * g->V1[1];
        g->values[c] = (1.0 - w) * g->u[l] + w * g->u[r];
        g->values[C + c] = (1.0 - w) * vl + w * vr;
        double d = g->u[r] - g->u[l];
        g->values[2 * C + c] = d * g->factor[c];
        g->values[3 * C + c] = d * g->inv_h[c];
    }
    for (long k = 0; k < 4 * C; k++)
        slot[k] = g->values[g->order[k]];
}
