/* The Coulomb slab kernel (coulomb.h) called on its own, for tests that
 * hold it to vstpetsc.kernels.coulomb.friction_integrals bit for bit
 * (tests/test_coulomb_native.py). */
#include "coulomb.h"

/* out: the FrictionSlab's ten numbers in its order; 0, or 1 when the
 * switches did not settle */
int vst_coulomb_slab(double e_n, double s1, double s2, double dt, double k_t, double mu,
                     const double *normal, const double *pieces, int count, double *out)
{
    FrictionSlab slab;
    int code = coulomb_friction_integrals(e_n, s1, s2, dt, k_t, mu, normal, pieces, count,
                                          &slab);
    if (code == 0) {
        out[0] = slab.f1; out[1] = slab.f2;
        out[2] = slab.d11; out[3] = slab.d12; out[4] = slab.d21; out[5] = slab.d22;
        out[6] = slab.stretch; out[7] = slab.slip; out[8] = slab.dissipation;
        out[9] = slab.released;
    }
    return code;
}
