# Two commands on a fresh machine: `make demo` and `make test`.
# Both create .venv, install what is missing (Debian's libfftw3-dev for SHTns), then run.
VENV   ?= .venv
PY     := $(VENV)/bin/python
STAMP  := $(VENV)/.installed
PYTHON ?= python3

.PHONY: demo test test-all bench docs fftw clean

demo: $(STAMP)
	$(VENV)/bin/spectralshell demo --out demo-output

test: $(STAMP)
	$(PY) -m pytest -m "not slow" -q

# the slow tests include the full validation report, kept in validation-report/
test-all: $(STAMP)
	SPECTRALSHELL_REPORT_DIR=validation-report $(PY) -m pytest -q

# every validation/bench_*.py -> validation/BENCHMARKS.md (one table) + validation/cost_growth.png
bench: $(STAMP)
	$(PY) validation/bench_table.py

# the documentation site -> docs/_build/html/index.html: API reference, the examples/ gallery and
# the notebooks (all executed), pages generated from the package's reports; warnings are errors
DOCS_STAMP := $(VENV)/.installed-docs

docs: $(STAMP) $(DOCS_STAMP)
	$(PY) -m sphinx -W --keep-going -b html docs docs/_build/html

$(DOCS_STAMP): pyproject.toml | $(STAMP)
	$(PY) -m pip install -q -e '.[test,docs]'
	@touch $(DOCS_STAMP)

# SHTns is built from its PyPI source and needs the FFTW3 headers.
fftw:
	@if [ ! -f /usr/include/fftw3.h ]; then \
	  if [ "$$(id -u)" = 0 ]; then \
	    echo "installing libfftw3-dev (needed to build SHTns)"; \
	    apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq libfftw3-dev >/dev/null; \
	  else \
	    echo "SHTns needs FFTW3 headers: run 'sudo apt-get install -y libfftw3-dev', then repeat this make command" >&2; exit 2; \
	  fi; \
	fi

$(PY):
	$(PYTHON) -m venv $(VENV)

$(STAMP): pyproject.toml spectralshell/solvers/_tridiagonal.c spectralshell/solvers/_schur.c \
	  spectralshell/special/_lentz.c | $(PY)
	@$(MAKE) --no-print-directory fftw
	$(PY) -m pip install -q --upgrade pip
	$(PY) -m pip install -q -e '.[test]'
	@touch $(STAMP)

clean:
	rm -rf $(VENV) demo-output .pytest_cache docs/_build docs/generated docs/auto_examples
