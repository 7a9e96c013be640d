"""The names of a result file (docs/result-file.md): every dataset name,
shared by both geometries (a plane-strain file's own in
:mod:`vstpetsc.results.plane_layout`).  The writer, the reader, the summary
and the plot take their names from here; what a model writes under them is
its room's layout (:mod:`vstpetsc.line.layout`, :mod:`vstpetsc.plane.layout`).

    /time                          (nt,)
    /body/<name>/x, u, v, stress   (nn,), (nt, nn), (nt, nn), (nt, ne)
    /body/<name>/stress_min, stress_max   (ne,) envelopes, rewritten with every block
    /body/<name>/shear/u, v, stress, stress_min, stress_max   the shear component, if any
    /<law group>/<series>          (nt,)   e.g. /contact/0/gap
    /energy/kinetic, strain, spring, damping, external, contact, soil, numerical   (nt,)
    /solver/newton_iterations, linear_iterations, wall_time, slab   (nt,)
    /gauge/<name>/u, v, stress, strain   (ns + 1,)   every slab, whatever `every` is
    /contact/<k>/events            (m, 2)  (time, +1 close / -1 open), with the blocks
"""

from vstpetsc.runner import energy as energy_mod

TIME = "time"
BODY = "body"
CONTACT = "contact"
EVENTS = "events"
ENERGY = tuple(f"energy/{k}" for k in energy_mod.KEYS)
ENVELOPES = ("stress_min", "stress_max")
ELONGATION = ("solver/elongation_min", "solver/elongation_max")   # the envelopes' exact state
SOLVER = ("solver/newton_iterations", "solver/linear_iterations", "solver/wall_time",
          "solver/slab")
INTEGER_SERIES = ("solver/newton_iterations", "solver/linear_iterations", "solver/slab")
BODY_SERIES = ("u", "v", "stress")
RHS_STATE = "solver/rhs_state"
NEWTON_STATE = "solver/newton_state"    # [acted, the laws' terms f] of the last slab
# the running sums of the energy terms (energy.SUMS order, then each rank's
# share of the external work): a restart continues the sums, not from the
# rounded totals of the rows, so its energies are those of one run
ENERGY_STATE = "solver/energy_sums"
# a hysteretic soil's state (vstpetsc.materials.soil: strains, stresses,
# reversal points, envelopes, the loops' work)
SOIL_STATE = "solver/soil_state"
RESTART_STATE = (RHS_STATE, NEWTON_STATE, ENERGY_STATE, SOIL_STATE)
REQUIRED = ("time", "body", "contact", "energy", "solver")
# root attributes: the rows (kept, and gauge rows) complete in every
# dataset, set after each block is on disk; readers of a running file read
# these many (results/writer.py Completed, results/reader.py)
COMPLETE_ROWS = "complete_rows"
COMPLETE_GAUGE_ROWS = "complete_gauge_rows"

# a gauge's series (docs/result-file.md, "/gauge"), and the prefix of the
# series a gauge on a body with a shear component adds
GAUGE_SERIES = ("u", "v", "stress", "strain")
SHEAR = "shear_"


def gauge_path(name=None, key=None):
    """The HDF5 path of the gauge group, of gauge ``name``, or of one of
    its series."""
    return "/".join(["gauge"] + [p for p in (name, key) if p is not None])


def text(value):
    """An attribute of the file as a str (h5py may hand back bytes)."""
    return value.decode() if isinstance(value, bytes) else str(value)


def body_path(name, key=None):
    return f"{BODY}/{name}" if key is None else f"{BODY}/{name}/{key}"


def is_events(name):
    """Whether dataset ``name`` is a pair's events: it grows by its own
    rows (with the blocks), not by one per kept slab."""
    parts = name.strip("/").split("/")
    return len(parts) == 3 and parts[0] == CONTACT and parts[2] == EVENTS


def grows(ds):
    """Whether dataset ``ds`` grows with the run (its first axis unlimited)."""
    return bool(ds.maxshape) and ds.maxshape[0] is None


def every_slab(name):
    """Whether series ``name`` has a row per slab (a gauge), not per kept slab."""
    return name.startswith("gauge/")


def by_group(laws, what):
    """{group: the merged dicts what(law) of its laws} (a pair's normal law
    and its friction share /contact/<k>)."""
    out = {}
    for law in laws:
        out.setdefault(law.group, {}).update(what(law))
    return out
