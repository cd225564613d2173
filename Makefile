# phmech -- two commands on a fresh machine:  make demo   and   make test
# Both install what is missing (Debian packages as root, a .venv with the PyPI packages),
# build phmech into .venv, then run. Both are idempotent and quick the second time.

PYTHON ?= python3
VENV   := .venv
PY     := $(VENV)/bin/python
STAMP  := $(VENV)/.phmech-deps
SOURCES := $(shell find csrc python -type f -name '*.[ch]' -o -type f -name '*.py') meson.build meson.options pyproject.toml

.PHONY: all demo test ctest pytest sanitize sundials7-check build sysdeps validate bench docs clean info wheel sdist

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
	@# every target, the extension too (meson test builds only what the tests link: a warning in
	@# csrc/pyext/ passed unseen)
	$(VENV)/bin/meson compile -C build/check-release
	$(VENV)/bin/meson test -C build/check-release --print-errorlogs

# pytest-xdist: one worker per core (PYTEST_WORKERS=0 runs in this process); --dist loadfile
# keeps each file in one worker, since tests/test_fuzz.py's last test counts the models its
# module built
PYTEST_WORKERS ?= auto
PYTEST_PAR     := -n $(PYTEST_WORKERS) --dist loadfile

pytest: build
	$(PY) -m pytest -q $(PYTEST_PAR) tests

# the docs too (Sphinx with warnings as errors), so that they cannot break unseen
test: ctest pytest sanitize docs

# AddressSanitizer + UndefinedBehaviorSanitizer (with float-cast-overflow): the core and the
# extension built in build/sanitize (the .venv's phmech is not touched), the C unit tests, then
# SAN_TESTS run against that build through PYTHONPATH. Python is not instrumented, so libasan is
# preloaded (with libstdc++, whose exception handling ASan intercepts), Python allocates with
# malloc (so ASan sees every buffer), leaks are not reported (the interpreter keeps its own) and
# the first UBSan report halts the run: any report fails `make sanitize`.
SAN_DIR   := build/sanitize
SAN_TESTS := tests/test_fuzz.py tests/test_fuzz_findings.py tests/test_error_messages.py \
             tests/test_se3.py tests/test_mixed.py tests/test_pairs.py tests/test_statics.py \
             tests/test_solver_robustness.py tests/test_rigid_body.py tests/test_beam_dynamics.py \
             tests/test_marshal.py tests/test_model_setup.py tests/test_progress.py tests/test_laws.py \
             tests/test_driven_pairs.py tests/test_modes_sparse.py tests/test_ida_linear_solvers.py \
             tests/test_components.py
SAN_ENV    = ASAN_OPTIONS=detect_leaks=0:abort_on_error=1 \
             UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1 PYTHONMALLOC=malloc
SAN_PRELOAD = $$(cc -print-file-name=libasan.so) $$(cc -print-file-name=libstdc++.so)

sanitize: sysdeps $(STAMP)
	@test -f $(SAN_DIR)/build.ninja || $(VENV)/bin/meson setup $(SAN_DIR) --buildtype=debugoptimized \
	  -Db_sanitize=address,undefined -Db_lundef=false -Db_lto=false -Dc_args=-fsanitize=float-cast-overflow \
	  -Dc_link_args=-fsanitize=float-cast-overflow >/dev/null
	$(VENV)/bin/meson compile -C $(SAN_DIR)
	$(SAN_ENV) $(VENV)/bin/meson test -C $(SAN_DIR) --print-errorlogs
	@rm -rf $(SAN_DIR)/pkg && mkdir -p $(SAN_DIR)/pkg/phmech
	@cp python/phmech/*.py $(SAN_DIR)/_core*.so $(SAN_DIR)/pkg/phmech/
	$(SAN_ENV) LD_PRELOAD="$(SAN_PRELOAD)" PYTHONPATH=$(SAN_DIR)/pkg PHMECH_FUZZ_LIMIT=60 \
	  $(PY) -c "import phmech; assert '$(SAN_DIR)' in phmech.__file__, phmech.__file__; print('sanitized phmech:', phmech.__file__)"
	$(SAN_ENV) LD_PRELOAD="$(SAN_PRELOAD)" PYTHONPATH=$(SAN_DIR)/pkg PHMECH_FUZZ_LIMIT=60 \
	  $(PY) -m pytest -q -p no:cacheprovider $(PYTEST_PAR) $(SAN_TESTS)

# SUNDIALS 7 (not part of `make test`, whose builds use Debian's 6.4.1): the core and the extension
# built in build/sun7 against the SUNDIALS 7.x installed at SUNDIALS7_PREFIX (release flags and
# -Werror, like ctest; meson's build rpath points at its libraries), the C unit tests, then
# SUN7_TESTS against that build through PYTHONPATH (the .venv's phmech is not touched).
# docs/building.md says what that install needs and what this run gave.
SUN7_DIR   := build/sun7
SUN7_TESTS := tests/test_se3.py tests/test_pairs.py tests/test_rigid_body.py \
              tests/test_beam_dynamics.py tests/test_statics.py tests/test_default_integrator.py \
              tests/paper/test_leaf_spring.py tests/test_generalized_alpha.py tests/test_topology.py \
              tests/test_info.py

sundials7-check: sysdeps $(STAMP)
	@test -n "$(SUNDIALS7_PREFIX)" || { echo "usage: make sundials7-check SUNDIALS7_PREFIX=<install prefix of SUNDIALS 7.x> (docs/building.md)" >&2; exit 2; }
	@if test -f $(SUN7_DIR)/build.ninja; then \
	  $(VENV)/bin/meson configure $(SUN7_DIR) -Dsundials_prefix=$(abspath $(SUNDIALS7_PREFIX)); \
	else \
	  $(VENV)/bin/meson setup $(SUN7_DIR) --buildtype=release -Dwerror=true \
	    -Dsundials_prefix=$(abspath $(SUNDIALS7_PREFIX)) >/dev/null; \
	fi
	$(VENV)/bin/meson compile -C $(SUN7_DIR)
	$(VENV)/bin/meson test -C $(SUN7_DIR) --print-errorlogs
	@rm -rf $(SUN7_DIR)/pkg && mkdir -p $(SUN7_DIR)/pkg/phmech
	@cp python/phmech/*.py $(SUN7_DIR)/_core*.so $(SUN7_DIR)/pkg/phmech/
	PYTHONPATH=$(SUN7_DIR)/pkg $(PY) -c "import io, phmech; v = phmech.info(file=io.StringIO())['sundials']; \
	  assert '$(SUN7_DIR)' in phmech.__file__ and v.startswith('7.'), (phmech.__file__, v); print('phmech', phmech.__file__, 'SUNDIALS', v)"
	PHMECH_EXPECT_SUNDIALS_MAJOR=7 PYTHONPATH=$(SUN7_DIR)/pkg $(PY) -m pytest -q -p no:cacheprovider $(SUN7_TESTS)

# The HTML documentation in build/docs/html: the pages of docs/ and the API reference generated
# from the docstrings of phmech.__all__ (Sphinx, autodoc, napoleon, myst-parser; docs/conf.py).
# Its packages (docs/requirements.txt) go into .venv (make docs, and so make test). -W: a
# warning fails the build; -E: every page re-read, so a warning is never hidden by the cache.
DOCS_STAMP := $(VENV)/.phmech-docs-deps

$(DOCS_STAMP): docs/requirements.txt $(STAMP)
	$(PY) -m pip install -q -r docs/requirements.txt
	@touch $@

docs: build $(DOCS_STAMP)
	$(PY) -m sphinx -W --keep-going -E -b html docs build/docs/html
	@echo "documentation: build/docs/html/index.html"

# A self-contained binary wheel in dist/: phmech built as for .venv (in its build directory,
# build/py: the same configuration, so nothing is compiled twice), then `auditwheel repair`
# copies every shared library the extension needs beyond glibc (SUNDIALS IDA and its KLU solver,
# KLU and the SuiteSparse parts it uses, LAPACK, BLAS, libgfortran, libquadmath) into
# phmech.libs/ inside the wheel, under the most compatible manylinux tag this machine's glibc
# allows (manylinux_2_34 on Debian 12). It installs with pip on a machine without the Debian
# development packages (README.md); tests/test_wheel.py installs it into a fresh venv and checks.
WHEEL_STAMP := $(VENV)/.phmech-wheel-deps

$(WHEEL_STAMP): tools/requirements-wheel.txt $(STAMP)
	$(PY) -m pip install -q -r tools/requirements-wheel.txt
	@touch $@

wheel: sysdeps $(WHEEL_STAMP)
	@rm -rf build/wheel-raw && rm -f dist/phmech-*.whl
	$(PY) -m pip wheel -q --no-build-isolation --no-deps -w build/wheel-raw -Cbuild-dir=build/py .
	PATH="$(abspath $(VENV))/bin:$$PATH" $(VENV)/bin/auditwheel repair -w dist build/wheel-raw/phmech-*.whl
	@ls -l dist/phmech-*.whl

# The source distribution in dist/ (meson-python: the files git tracks).
sdist: sysdeps $(WHEEL_STAMP)
	@rm -f dist/phmech-*.tar.gz
	$(PY) -m build --sdist --no-isolation --outdir dist .

# Long validation studies (not part of `make test`); figures land in benchmarks/results/.
# hard_cases.py: the long versions of tests/hard (docs/validation.md), ~5 min CPU.
# validate_urdf.py: UR5 and Panda against Pinocchio (tools/requirements-validate.txt: pin and
# example-robot-data, the [validate] extra, installed into .venv here only), ~11 s CPU.
VALIDATE_STAMP := $(VENV)/.phmech-validate-deps

$(VALIDATE_STAMP): tools/requirements-validate.txt $(STAMP)
	$(PY) -m pip install -q -r tools/requirements-validate.txt
	@touch $@

# integrator_contract.py: the long versions of tests/accuracy/test_integrator_contract.py.
# configuration_error.py: scenes.py's flexible scenes in the accuracy contract's own norm (~1 min).
validate: build $(VALIDATE_STAMP)
	@mkdir -p benchmarks/results
	$(PY) examples/timoshenko_table.py --json --plot benchmarks/results/timoshenko_convergence.png > benchmarks/results/timoshenko_table.json
	$(PY) benchmarks/validate_energy_drift.py
	$(PY) benchmarks/all_state_reference.py
	$(PY) benchmarks/hard_cases.py
	$(PY) benchmarks/sizing.py
	$(PY) benchmarks/validate_urdf.py
	$(PY) benchmarks/integrator_contract.py
	$(PY) benchmarks/configuration_error.py

# Work-precision benchmarks against Exudyn, MuJoCo and PyElastica (pinned in
# benchmarks/requirements.txt, installed into .venv here, not for `make test`);
# BENCH_ARGS=--quick for a short run. Results: benchmarks/results/*.json and *.png; the last step
# rewrites the marked tables of README.md, docs/performance.md and docs/perf_*.md from them
# (benchmarks/report.py --write-docs; without the option it prints them).
# A smoke of every script below (--smoke, seconds each) runs in `make test`
# (tests/test_benchmarks_smoke.py; peers skipped there when not installed).
BENCH_STAMP := $(VENV)/.phmech-bench-deps

$(BENCH_STAMP): benchmarks/requirements.txt $(STAMP)
	$(PY) -m pip install -q -r benchmarks/requirements.txt
	@touch $@

bench: build $(BENCH_STAMP)
	$(PY) benchmarks/scenes.py $(BENCH_ARGS)
	$(PY) benchmarks/run.py $(BENCH_ARGS)
	$(PY) benchmarks/bench_scaling.py $(BENCH_ARGS)
	$(PY) benchmarks/bench_leaf_spring.py $(BENCH_ARGS)
	$(PY) benchmarks/bench_modal.py $(BENCH_ARGS)
	$(PY) benchmarks/mass_matrix_study.py $(BENCH_ARGS)
	$(PY) benchmarks/bench_large.py $(BENCH_ARGS)
	$(PY) benchmarks/bench_overhead.py $(BENCH_ARGS)
	$(PY) benchmarks/report.py --write-docs

clean:
	rm -rf build $(VENV)/.phmech-built
