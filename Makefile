# Every set-up step lives here: `make demo` and `make test` work from a fresh
# clone on a fresh Debian 12 machine (as root; sudo is used when not root).
SHELL := /bin/bash
VENV  := .venv
PY    := $(VENV)/bin/python
SUDO  := $(shell [ "$$(id -u)" = 0 ] || echo sudo)
# Debian's PETSc 3.18 (real scalars; libpetsc-real3.18-dev provides the
# /usr/lib/petsc alternative that petsc4py's .pth file looks for).
DEBS  := python3-petsc4py python3-mpi4py python3-h5py python3-numpy python3-scipy \
         python3-matplotlib python3-threadpoolctl python3-pytest python3-pytest-xdist python3-hypothesis python3-venv \
         python3-setuptools python3-pip libpetsc-real3.18-dev libmetis5 openmpi-bin gcc libc6-dev hdf5-tools
STAMP := $(VENV)/.installed
# the compiled kernels (vstpetsc/native: the Newton for penalty pairs, the
# end of a slab, the copies of kept rows); no fused multiply-adds, so that
# they repeat the Python path's arithmetic
NATIVE := vstpetsc/native/libvstnative.so

# OpenMPI refuses root without these; oversubscribe lets 2 ranks share 1 core.
export OMPI_ALLOW_RUN_AS_ROOT := 1
export OMPI_ALLOW_RUN_AS_ROOT_CONFIRM := 1
export OMPI_MCA_rmaps_base_oversubscribe := 1
export MPLBACKEND := agg

.PHONY: install demo test test-portable bench bench-quick bench-parallel bench-opensees soak clean formulations figures accuracy

install: $(STAMP) $(NATIVE)

$(NATIVE): $(wildcard vstpetsc/native/*.c vstpetsc/native/*.h) $(STAMP)
	gcc -O3 -fopenmp-simd -fPIC -shared -ffp-contract=off -Wall -Wextra -o $@ $(filter %.c,$^) -lm

$(STAMP): pyproject.toml
	@missing=$$(for p in $(DEBS); do dpkg-query -W -f='$${Status}\n' $$p 2>/dev/null | grep -q 'install ok installed' || echo $$p; done); \
	if [ -n "$$missing" ]; then \
	  echo "installing Debian packages: $$missing"; \
	  $(SUDO) apt-get update -qq && DEBIAN_FRONTEND=noninteractive $(SUDO) apt-get install -y -qq $$missing; \
	fi
	/usr/bin/python3 -m venv --system-site-packages $(VENV)
	$(PY) -m pip install --no-build-isolation --no-deps --disable-pip-version-check -q -e .
	$(PY) -c "import petsc4py, mpi4py, h5py, numpy; print('vstpetsc installed with PETSc', __import__('petsc4py').__version__)"
	touch $(STAMP)

demo: install
	$(VENV)/bin/vstpetsc run examples/bar-wall.toml -o demo.h5
	@echo "demo result written to $$(pwd)/demo.h5"

# VTK's XDMF reader, for tests/test_plane_outputs.py to open `export --xdmf`'s
# files as ParaView does.  PyPI's vtk: Debian 12's python3-vtk9 (9.1) is built
# without the Xdmf modules (a 140 MB wheel, 570 MB installed; the test skips
# without it).
VTK := $(VENV)/.vtk

$(VTK): $(STAMP)
	$(PY) -m pip install --no-deps --disable-pip-version-check -q vtk==9.7.2 && touch $@ || \
	  echo "WARNING: PyPI's vtk could not be installed: the XDMF reader checks will skip"

# two workers (pytest-xdist), the modules that start several ranks on one of them
test: install $(VTK)
	$(PY) -m pytest -q -n 2 --dist loadgroup tests

# The suite as other x86-64 CPUs run it: numpy's SIMD dispatch narrowed,
# OpenBLAS's kernel of an older CPU, the C kernels built for the baseline
# and for this CPU (tests/portable.py; about three times `make test`).
test-portable: install $(VTK)
	$(PY) tests/portable.py

clean:
	rm -rf $(VENV) build *.egg-info demo.h5 $(NATIVE)

formulations: install
	$(PY) docs/compare_formulations.py

figures: install
	$(PY) docs/make_figures.py

# openseespy (PyPI) for bench/opensees.py, bench/plane_opensees.py,
# bench/plane_yielding_opensees.py and bench/plane_acoustic_opensees.py only:
# `make test` never needs it (their tests skip without it).
OPENSEES := $(VENV)/.opensees

$(OPENSEES): $(STAMP)
	$(PY) -m pip install --disable-pip-version-check -q openseespy
	touch $@

# Speed is measured here, never asserted in tests.
bench: install $(OPENSEES)
	$(PY) bench/run.py
	$(PY) bench/opensees.py
	$(PY) bench/plane_opensees.py
	$(PY) bench/parallel_solvers.py
	$(PY) bench/soil_cost.py
	$(PY) bench/friction_cost.py 64 7
	$(PY) bench/plane_solvers.py 10000 100000 --courant 1,4
	$(PY) bench/plane_slab.py
	$(PY) bench/plane_memory.py
	$(PY) bench/plane_parallel.py
	$(PY) bench/plane_dam_ranks.py
	$(PY) bench/plane_interfaces.py
	$(PY) bench/plane_yielding.py
	$(PY) bench/plane_yielding_opensees.py
	$(PY) bench/plane_water.py
	$(PY) bench/plane_acoustic_opensees.py
	$(PY) bench/blas_threads.py
	$(PY) bench/sweep_speed.py
	$(PY) bench/pile_speed.py
	$(PY) bench/run_overhead.py --readme

bench-quick: install
	$(PY) bench/run.py --quick --out bench/quick

bench-opensees: install $(OPENSEES)
	$(PY) bench/opensees.py
	$(PY) bench/plane_opensees.py

bench-parallel: install
	$(PY) bench/parallel_solvers.py

# The accuracy studies' tables (studies/README.md; bench/ holds timing only):
# bar-wall by variant and Courant number, against the mesh, and the
# standing wave (docs/accuracy.md); waves by mass matrix
# (docs/wave-accuracy.md); D(ky) and the flexible column, with their two
# figures (docs/sliding-block.md).
accuracy: install
	$(PY) studies/impact_study.py impact
	$(PY) studies/impact_study.py mesh
	$(PY) studies/impact_study.py moved
	$(PY) studies/impact_study.py wave
	$(PY) studies/impact_study.py cost
	$(PY) studies/wave_study.py wave
	$(PY) studies/wave_study.py site
	$(PY) studies/wave_study.py rigid
	$(PY) studies/wave_study.py semi
	$(PY) studies/sliding_study.py

# The reliability catalogue many times over (random kills, signals, full disks).
soak: install
	$(PY) bench/soak.py
