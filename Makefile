# Two entry points for a newcomer; each sets everything up first (a local .venv).
VENV ?= .venv
PY := $(VENV)/bin/python

.PHONY: demo test docs asan

# pip -qq: setuptools' generic advice on editable installs is not for a newcomer's screen
# (errors still print)
$(VENV)/.installed: pyproject.toml
	python3 -m venv $(VENV)
	$(PY) -m pip install --quiet --upgrade pip
	$(PY) -m pip install -qq -e '.[test]'
	touch $@

# the main job: the stick-slip scene, its result table, CSV, JSON and plot in out/
demo: $(VENV)/.installed
	$(VENV)/bin/mechfmu run stick_slip --out out

# the API reference, generated from the docstrings (pdoc): docs/api/index.html
# (pdoc comes with the test extra that .venv installs; elsewhere: pip install -e '.[docs]')
DOCS_OUT ?= docs/api
docs: $(VENV)/.installed
	$(PY) docs/build_api.py $(DOCS_OUT)

# the test suite, a file per worker on every core (pytest-xdist: FMU builds and runs are
# CPU-bound); pytest's exit code 5 (nothing collected) is a failure, not green
test: $(VENV)/.installed
	$(PY) -m pytest -q -n auto --dist loadfile; rc=$$?; \
	if [ $$rc -eq 5 ]; then echo "pytest collected no tests: failing"; exit 1; fi; exit $$rc

# the FMU, engine, assembly-FMU and fuzz tests with every library mechfmu compiles built
# with AddressSanitizer + UBSan (MECHFMU_SANITIZE=1: fmus/build.py), the ASan runtime
# preloaded into Python (ctypes loads the libraries; libstdc++ too, so that the C++
# extensions' exceptions pass ASan's interceptor); then a leak check: fuzz walks over
# every FMU (components and assembly FMUs, each instance freed) with LeakSanitizer at
# each child's exit; benchmarks/sanitizer_reports.py counts the reports (0 to pass).
# Leaks are not checked in the test run itself: Python keeps memory at exit by design,
# and a leak exit code would fail tests that check their children's exit codes.
SANITIZER_LOGS ?= /tmp/mechfmu-sanitizers
ASAN_TESTS := tests/integration/test_fmu_api.py tests/integration/test_fmu_steps.py \
	tests/integration/test_fmu_state.py tests/integration/test_engine_cosim.py \
	tests/integration/test_engine_me.py tests/integration/test_engine_guards.py \
	tests/integration/test_assembly_fmu.py tests/integration/test_hostile_assembly_fmu.py \
	tests/integration/test_fuzz.py tests/integration/test_value_types.py \
	tests/integration/test_restore_check.py tests/integration/test_fmi_termination.py \
	tests/integration/test_me_foreign_models.py tests/integration/test_engine_me_loops.py \
	tests/integration/test_me_time_functions.py tests/integration/test_cosim_input_jump.py \
	tests/integration/test_cosim_coast.py tests/integration/test_cosim_evaluated.py \
	tests/integration/test_me_local_events.py tests/integration/test_me_taken_members.py \
	tests/integration/test_rate_inputs.py
SANITIZED = MECHFMU_SANITIZE=1 \
	LD_PRELOAD="$$(gcc -print-file-name=libasan.so) $$(gcc -print-file-name=libstdc++.so)" \
	UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1:log_path=$(SANITIZER_LOGS)/ubsan
asan: $(VENV)/.installed
	rm -rf $(SANITIZER_LOGS) && mkdir -p $(SANITIZER_LOGS)
	$(SANITIZED) ASAN_OPTIONS=detect_leaks=0:log_path=$(SANITIZER_LOGS)/asan \
	$(PY) -m pytest -q -n auto --dist loadfile $(ASAN_TESTS); rc=$$?; \
	$(SANITIZED) ASAN_OPTIONS=detect_leaks=1:log_path=$(SANITIZER_LOGS)/leak LSAN_OPTIONS=exitcode=0 \
	$(PY) -m benchmarks.fuzz --calls 2800 --chunk 100 || rc=1; \
	$(PY) -m benchmarks.sanitizer_reports $(SANITIZER_LOGS) || rc=1; exit $$rc
