# Two entry points for a newcomer; each sets everything up first (a local .venv).
VENV ?= .venv
PY := $(VENV)/bin/python

.PHONY: demo test

$(VENV)/.installed: pyproject.toml
	python3 -m venv $(VENV)
	$(PY) -m pip install --quiet --upgrade pip
	$(PY) -m pip install --quiet -e '.[test]'
	touch $@

# the main job: the stick-slip scene, its result table, CSV, JSON and plot in out/
demo: $(VENV)/.installed
	$(VENV)/bin/mechfmu run stick_slip --out out

# the test suite, a file per worker on every core (pytest-xdist: FMU builds and runs are
# CPU-bound); pytest's exit code 5 (nothing collected) is a failure, not green
test: $(VENV)/.installed
	$(PY) -m pytest -q -n auto --dist loadfile; rc=$$?; \
	if [ $$rc -eq 5 ]; then echo "pytest collected no tests: failing"; exit 1; fi; exit $$rc
