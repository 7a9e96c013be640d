"""Stiffness that grows with confinement (issue 46 item 3; [[region]]
``confinement = { p_ref, exponent }``, docs/nonlinear-soil.md section 8).

Each cell of a confined region has Lame's lambda and mu (so its G, its
bulk modulus, its wave speeds squared; nu unchanged) and, when the region
yields, its gamma_ref scaled by

    f = (p / p_ref)^exponent,

p = (sigma_xx + sigma_yy + sigma_zz) / 3 with compression positive (here
p = -(1 + nu) (sigma_xx + sigma_yy) / 3, sigma_zz = nu (sigma_xx +
sigma_yy) in plane strain) at the cell's centre in the static start,
kept for the run.  The slab matrices (K, the Rayleigh damping's beta K,
the absorbing curves' dashpots beside a confined cell) and the yielding
zone are built from the scaled moduli.

The static start is then consistent: it is solved with the scaled moduli
it gives.  Since p depends on the moduli where the stiffness varies, the
factors are a fixed point, found by repeating: static solve with the
current factors (1 at first) -> p per cell -> the new factors; until no
factor changes by more than SETTLED of itself.  The plain repetition
contracts by about the exponent a round on a zoned dam (rockfill-dam-mkz:
0.49, 38 solves to 1e-12); each round's step is therefore relaxed by
Irons and Tuck's (1969) factor omega_k = -omega_{k-1} r_{k-1}.(r_k -
r_{k-1}) / |r_k - r_{k-1}|^2 (r the change the solve asked for; a step
that would make a factor non-positive is not relaxed), which takes it
there in 22 (the run keeps the last
static state and the factors it was solved with, an exact equilibrium of
the run's matrices).  A column held laterally has p = (1 + 2 K0) / 3 rho g
depth, K0 = nu / (1 - nu), whatever its stiffness: the second solve
confirms the first.  At most ROUNDS solves, then an InputError naming the
confined regions.  A confined cell whose p <= 0 (not compressed) is an
InputError naming its region's key, the cell (the mesh as read) and its
centre.

The factors are computed on rank 0 (the whole mesh, the static solve's
numbering as read) and broadcast; each rank takes its cells' by their
numbers as read (LocalMesh.original_cells)."""

import numpy as np

from vstpetsc.errors import InputError

ROUNDS = 30
SETTLED = 1e-12


def confined(case):
    """Whether a [[region]] of the case has ``confinement``."""
    return any(r.confinement is not None for r in case.plane.regions)


def confined_static(model):
    """The static start (vstpetsc.plane.solver.static.PlaneStatic) of a
    model with confined regions, its moduli scaled by the factors the
    start gives, the zone rebuilt with them (collective)."""
    from vstpetsc.plane.loads import gravity_pattern
    from vstpetsc.plane.solver.static import static_state

    base = _moduli(model)
    factors = np.ones(model.ncells)
    relax, last = 1.0, None
    for _ in range(ROUNDS):
        static = static_state(model, gravity_pattern(model))
        change = _shared_factors(model, static.u) - factors
        moved = np.max(np.abs(change) / factors, initial=0.0)
        if moved <= SETTLED:
            if model.zone is not None:
                model.zone = model._zone()
            return static
        relax, last = _relaxation(relax, last, change), change
        step = factors + relax * change
        factors = step if (step > 0.0).all() else factors + change
        scale(model, base, factors)
    names = ", ".join(f"region[{i}] ({r.name}).confinement"
                      for i, r in enumerate(model.case.plane.regions) if r.confinement)
    raise InputError(f"{names}: the static start and the moduli it gives did not settle in "
                     f"{ROUNDS} solves (a factor still changed by {moved:.3g} of itself)")


def _relaxation(relax, last, change):
    """Irons and Tuck's relaxation factor for the step ``change`` after
    ``last`` (None: the first step, 1)."""
    if last is None:
        return 1.0
    d = change - last
    dd = float(d @ d)
    return relax if dd == 0.0 else -relax * float(last @ d) / dd


def _moduli(model):
    """Copies of the unscaled lambda, mu: this rank's cells', and rank 0's
    of the whole mesh (None elsewhere)."""
    local = {k: model.materials[k].copy() for k in ("lam", "mu")}
    whole = {k: model.cell_materials[k].copy() for k in ("lam", "mu")} \
        if model.comm.getRank() == 0 else None
    return local, whole


def scale(model, base, factors):
    """The model's moduli ``base`` (_moduli) times ``factors`` (one per
    cell of the mesh as read, every rank): its materials, its boundaries'
    dashpots; its matrices to be assembled again."""
    from vstpetsc.plane import curves

    local, whole = base
    mine = factors[model.local.original_cells]
    for key in ("lam", "mu"):
        model.materials[key] = local[key] * mine
        if whole is not None:
            model.cell_materials[key] = whole[key] * factors
    model.factors = factors
    model.release_matrices()
    model.boundaries = curves.Boundaries(model, model.case.plane.boundaries)


def _shared_factors(model, u):
    """Rank 0's factors (factors) broadcast, or its InputError raised on
    every rank (collective)."""
    out = error = None
    if model.comm.getRank() == 0:
        try:
            out = factors(model.case, model.mesh, model.cell_materials, u)
        except InputError as exc:
            error = str(exc)
    if model.comm.getSize() > 1:
        out, error = model.comm.tompi4py().bcast((out, error), root=0)
    if error is not None:
        raise InputError(error)
    return out


def mean_stress(mesh, mat, u):
    """Each cell's p = -(sigma_xx + sigma_yy + sigma_zz) / 3 at its centre
    under the displacements u (nn, 2) (plane strain: sigma_zz = lambda
    (eps_xx + eps_yy) = nu (sigma_xx + sigma_yy))."""
    from vstpetsc.plane.energy import centre_stress

    stress = centre_stress(mesh, np.ravel(u), mat["lam"], mat["mu"])
    nu = mat["lam"] / (2.0 * (mat["lam"] + mat["mu"]))
    return -(1.0 + nu) * (stress[:, 0] + stress[:, 1]) / 3.0


def factors(case, mesh, mat, u):
    """(p / p_ref)^exponent of each cell of a confined region (1 elsewhere)
    from the static displacements u; InputError naming the first confined
    cell with p <= 0."""
    p = mean_stress(mesh, mat, u)
    out = np.ones(mesh.ncells)
    for i, r in enumerate(case.plane.regions):
        if r.confinement is None:
            continue
        cells = np.flatnonzero(mesh.region == mesh.region_names.index(r.name))
        loose = cells[p[cells] <= 0.0]
        if loose.size:
            c = int(loose[0])
            corners = mesh.cells[c][mesh.cells[c] >= 0]
            x, y = mesh.coordinates[corners].mean(axis=0)
            raise InputError(f"region[{i}] ({r.name}).confinement: cell {c} at ({x:.6g}, "
                             f"{y:.6g}) has mean stress p = {p[c]:.6g} <= 0 at the static "
                             f"start (compression positive; {loose.size} such cells): "
                             "its moduli cannot scale with (p / p_ref)^exponent")
        conf = r.confinement
        out[cells] = (p[cells] / conf["p_ref"]) ** conf["exponent"]
    return out
