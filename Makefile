# Two commands on a fresh machine: `make demo` and `make test`. Each creates or
# reuses the virtual environment in .venv and installs what it needs.
VENV ?= .venv
PY := $(VENV)/bin/python
STAMP := $(VENV)/.installed-stamp

.PHONY: demo test bench install clean

demo: $(STAMP)
	$(VENV)/bin/hitogata demo --out demo

test: $(STAMP) tools/node_modules/.package-lock.json
	$(PY) -m pytest -q

bench: $(STAMP)
	for b in benchmarks/bench_*.py; do $(PY) $$b || exit 1; done

install: $(STAMP)

$(STAMP): pyproject.toml
	test -x $(PY) || python3 -m venv $(VENV)
	$(PY) -m pip install -q --upgrade pip
	$(PY) -m pip install -q -e '.[test]'
	touch $@

# The Khronos glTF validator (npm) checks our GLB files in the tests.
tools/node_modules/.package-lock.json: tools/package-lock.json
	npm ci --prefix tools --no-audit --no-fund

clean:
	rm -rf $(VENV) tools/node_modules demo
