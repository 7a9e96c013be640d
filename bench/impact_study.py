import io, sys, numpy as np, vstpetsc, tempfile, os, itertools
tmp = tempfile.mkdtemp()
E, rho, L, v0 = 2e11, 7850.0, 1.0, 1.0
c = np.sqrt(E/rho); Z = rho*c
def bar_wall(n, courant, mass, form, beta=None):
    dt = courant * L / n / c
    T = 1e-3/c/1 + 2*L/c
    end = 0.001/v0 + 2*L/c + 0.5*L/c
    pair = {"pair": ["bar", "wall"], "wall": L + 0.001, "formulation": form}
    if beta is not None:
        k = beta * E * n / L
        pair["penalty"] = k if form == "power" else 2*k/dt
    doc = {"time": {"dt": dt, "end": end}, "output": {"every": 1},
           "body": [{"name": "bar", "x": [0.0, L], "elements": n, "E": E, "rho": rho, "v0": v0, "mass": mass}],
           "contact": [pair]}
    r = vstpetsc.run(vstpetsc.Case.from_dict(doc), output=os.path.join(tmp, "r.h5"), quiet=True, out=io.StringIO())
    f = r.contact(0).force[:] / (Z*v0)
    on = f > 1e-3
    plateau = np.median(f[on])
    v = r.body("bar").v[-1]; 
    # rebound: mean velocity = momentum / mass
    m = rho*L
    vm = np.mean(v)  # approx (uniform mesh): use trapezoid
    x = r.body("bar").x[:]
    vm = np.trapz(v, x)/L
    e = r.energy; tot = e["kinetic"][-1] + e["strain"][-1]
    e0 = 0.5*m*v0**2
    return f.max(), plateau, (-vm - v0)/v0, (tot-e0)/e0
for form, beta in [("seed", None), ("power", None), ("power", 0.5)]:
    for mass in ["consistent", "averaged", "lumped"]:
        for courant in [1.0, 0.5, 0.25]:
            pk, pl, reb, en = bar_wall(100, courant, mass, form, beta)
            print(f"{form:6s} beta={beta} {mass:10s} C={courant:4.2f} peak {pk:.3f} plateau {pl:.4f} rebound {reb:+.4%} energy {en:+.4%}", flush=True)
