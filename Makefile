# phmech -- two commands on a fresh machine:  make demo   and   make test
# Both install what is missing (Debian packages as root, a .venv with the PyPI packages),
# build phmech into .venv, then run. Both are idempotent and quick the second time.

PYTHON ?= python3
VENV   := .venv
PY     := $(VENV)/bin/python
STAMP  := $(VENV)/.phmech-deps
SOURCES := $(shell find csrc python -type f -name '*.[ch]' -o -type f -name '*.py') meson.build pyproject.toml

.PHONY: all demo test ctest pytest build sysdeps validate bench clean info

all: build

sysdeps:
	@bash tools/system-deps.sh

$(STAMP): tools/requirements-dev.txt | sysdeps
	@test -x $(PY) || $(PYTHON) -m venv $(VENV)
	$(PY) -m pip install -q --upgrade pip
	$(PY) -m pip install -q -r tools/requirements-dev.txt
	@touch $@

# pip builds in build/py, so a rebuild recompiles only what changed.
$(VENV)/.phmech-built: $(STAMP) $(SOURCES)
	$(PY) -m pip install -q --no-build-isolation --no-deps -Cbuild-dir=build/py .
	@touch $@

build: sysdeps $(VENV)/.phmech-built

info: build
	$(PY) -c "import phmech; phmech.info()"

demo: build
	$(PY) -c "import phmech; phmech.info()"
	$(PY) examples/leaf_spring.py --quick

ctest: sysdeps $(STAMP)
	@# the flags of the shipped build (release, -O3) with -Werror: some warnings (e.g.
	@# -Wmaybe-uninitialized) appear only when optimizing
	@test -f build/check-release/build.ninja || $(VENV)/bin/meson setup build/check-release --buildtype=release -Dwerror=true >/dev/null
	$(VENV)/bin/meson test -C build/check-release --print-errorlogs

pytest: build
	$(PY) -m pytest -q tests

test: ctest pytest

# Long validation studies (not part of `make test`); figures land in benchmarks/results/.
validate: build
	@mkdir -p benchmarks/results
	$(PY) examples/timoshenko_table.py --json --plot benchmarks/results/timoshenko_convergence.png > benchmarks/results/timoshenko_table.json
	$(PY) benchmarks/validate_energy_drift.py
	$(PY) benchmarks/all_state_reference.py

# Work-precision benchmarks against Exudyn and MuJoCo (installed into .venv from
# benchmarks/requirements.txt when missing); BENCH_ARGS=--quick for a short run (~4.5 min instead
# of ~25 min on 2 cores). Results: benchmarks/results/*.json and *.png; summary: docs/performance.md.
bench: build
	$(PY) benchmarks/scenes.py $(BENCH_ARGS)
	$(PY) benchmarks/run.py $(BENCH_ARGS)
	$(PY) benchmarks/bench_scaling.py $(BENCH_ARGS)
	$(PY) benchmarks/bench_leaf_spring.py $(BENCH_ARGS)
	$(PY) benchmarks/mass_matrix_study.py

clean:
	rm -rf build $(VENV)/.phmech-built
