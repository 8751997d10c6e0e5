# Two commands on a fresh machine: `make demo` and `make test`. Each creates or
# reuses the virtual environment in .venv and installs what it needs.
VENV ?= .venv
PY := $(VENV)/bin/python
STAMP := $(VENV)/.installed-stamp

.PHONY: demo test test-fast repin lint bench install clean system-render system-test

demo: system-render $(STAMP)
	$(VENV)/bin/hitogata demo --out demo --force  # a second run replaces the first one's files

# The linter and the type checker (configured in pyproject.toml) before the tests, which run on two
# processes (pytest-xdist; tests/conftest.py says what runs together): 21-26 min on two otherwise idle cores (a fresh
# clone), about 50 min with another job holding one core.
# Deselect what a machine cannot run: make test PYTEST_ARGS='-m "not browser"'; one process: PYTEST_ARGS=-n0
test: system-test $(STAMP) tools/node_modules/.package-lock.json lint
	$(PY) -m pytest -q -n 2 --dist loadscope $(PYTEST_ARGS)

# The unit tests alone: no elastic model nor whole-body mesh built (slow), no workflow end to end (integration),
# no browser nor offscreen pictures; two processes. 900 tests: 7 min on two cores shared with four other jobs
# (load 5-7; the wider not-slow set took 33 min in one process there), so about 2.5 min on two idle cores.
test-fast: $(STAMP)
	$(PY) -m pytest -q -n 2 --dist loadscope -m "not slow and not integration and not browser and not render" $(PYTEST_ARGS)

# Regression figures live in tests/golden/ (tests/golden.py). After a change that moves them on purpose:
# make repin TESTS=tests/skin/test_extreme_poses.py  (one process) lists each moved figure, old and new, then
# the golden files' diff; the change says why each moved (CHANGELOG.md or its decision).
TESTS ?= tests
repin: $(STAMP)
	$(PY) -m pytest -q -n0 --repin $(TESTS)
	git diff --stat -- tests/golden

lint: $(STAMP)
	$(VENV)/bin/ruff check src tests benchmarks
	$(VENV)/bin/mypy

# Debian packages, installed only when missing (tools/install_system_deps.sh says which and why).
system-render:
	bash tools/install_system_deps.sh render

system-test:
	bash tools/install_system_deps.sh test

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
