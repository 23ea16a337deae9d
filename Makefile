# smodrive: the two Quickstart commands are `make reproduce` and `make test`.
# Both create a local virtual environment (.venv) and build the package in it;
# `make test` also installs the Cortex-M4F cross compiler and emulator
# (Debian's gcc-arm-none-eabi, qemu-system-arm) when they are missing: the
# firmware build is tested, and run on an emulated Cortex-M4F.

PY ?= python3
VENV := .venv
BIN := $(VENV)/bin
OUT ?= results
STAMP := $(VENV)/.installed
# the package with the extras test and docs (Sphinx): what `make test` installs,
# the documentation build is a test
DOCS_STAMP := $(VENV)/.docs-installed
SOURCES := $(shell find core sim src -type f \( -name '*.c' -o -name '*.h' -o -name '*.py' -o -name '*.toml' \)) \
           CMakeLists.txt pyproject.toml
SUDO := $(shell [ "$$(id -u)" = 0 ] || echo sudo)
# parallel jobs of the C build, ctest and pytest (pytest-xdist workers)
JOBS ?= $(shell nproc 2>/dev/null || echo 2)

.PHONY: all install reproduce test ctest pytest toolchain bench clean dev

all: test

# pip is upgraded when the venv is made; each install builds the C library
# (scikit-build-core), so `make test` installs the package once, with both
# extras ($(DOCS_STAMP) below), not once for each
$(STAMP): $(SOURCES)
	@[ -x $(BIN)/python ] || { $(PY) -m venv $(VENV) && $(BIN)/python -m pip install -q --upgrade pip; }
	$(BIN)/python -m pip install -q ".[test]"
	@touch $(STAMP)

install: $(STAMP)

reproduce: $(STAMP) toolchain
	$(BIN)/smodrive reproduce --out $(OUT)

toolchain:
	@command -v arm-none-eabi-gcc >/dev/null 2>&1 && command -v qemu-system-arm >/dev/null 2>&1 && \
	 command -v clang >/dev/null 2>&1 && command -v cppcheck >/dev/null 2>&1 && \
	 command -v valgrind >/dev/null 2>&1 && \
	 ls "$$(clang -print-resource-dir)"/lib/linux/libclang_rt.fuzzer-*.a >/dev/null 2>&1 || { \
	  echo "installing from Debian: the Cortex-M4F cross compiler and emulator (gcc-arm-none-eabi, qemu-system-arm), clang with libFuzzer and the sanitizers (clang, libclang-rt-dev), cppcheck, valgrind (the C tests' memcheck)"; \
	  $(SUDO) apt-get update -qq && \
	  $(SUDO) env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends \
	    gcc-arm-none-eabi libnewlib-arm-none-eabi qemu-system-arm clang libclang-rt-dev cppcheck \
	    valgrind >/dev/null; }

# The simulator's objects are not built here (SMD_BUILD_SIM=OFF): no C test
# links them (the fuzz targets compile the plant themselves), and the package
# install builds them with the same warnings as errors.
ctest: toolchain
	cmake -S . -B build/ctest -DSMD_BUILD_TESTS=ON -DSMD_BUILD_PYLIB=OFF -DSMD_BUILD_SIM=OFF \
	  -DCMAKE_BUILD_TYPE=Release >/dev/null
	cmake --build build/ctest -j $(JOBS)
	ctest --test-dir build/ctest --output-on-failure -j $(JOBS)

# -n: pytest-xdist, the units of work of tests/conftest.py
pytest: $(DOCS_STAMP) toolchain
	$(BIN)/python -m pytest -q -n $(JOBS)

test: ctest pytest

# Longer fuzzing (docs/testing.md): every libFuzzer target for FUZZ_SECONDS
# each, its working corpus kept in build/fuzz/ from run to run.
FUZZ_SECONDS ?= 600
.PHONY: fuzz
fuzz: toolchain
	cmake -S . -B build/ctest -DSMD_BUILD_TESTS=ON -DSMD_BUILD_PYLIB=OFF -DSMD_BUILD_SIM=OFF \
	  -DCMAKE_BUILD_TYPE=Release >/dev/null
	cmake --build build/ctest -j $(JOBS)
	sh fuzz/run_long.sh $(FUZZ_SECONDS)

# Development: the C library built into src/smodrive, so that
# `PYTHONPATH=src .venv/bin/python -m pytest` runs the working tree.
dev: $(STAMP)
	cmake -S . -B build/dev -DSMD_BUILD_TESTS=OFF -DSMD_BUILD_PYLIB=ON >/dev/null
	cmake --build build/dev -j 2
	for l in libsmodrive libsmodrive_fast; do \
	  cp build/dev/$$l.so src/smodrive/.$$l.so.tmp && \
	  mv src/smodrive/.$$l.so.tmp src/smodrive/$$l.so; \
	done  # atomic: running tests keep the old one

# The documentation site (Sphinx: docs/, the API reference from the
# docstrings, the parameter reference from the dataclass metadata, the
# gallery of examples/) into build/docs; its tools are the extra `docs`.
$(DOCS_STAMP): $(SOURCES)
	@[ -x $(BIN)/python ] || { $(PY) -m venv $(VENV) && $(BIN)/python -m pip install -q --upgrade pip; }
	$(BIN)/python -m pip install -q ".[test,docs]"
	@touch $(STAMP) $(DOCS_STAMP)

# built from a copy (build/docs-src): the generated API stubs and gallery
# stay out of docs/; a warning fails the build (-W), after all of them are
# listed (--keep-going)
.PHONY: docs
docs: $(DOCS_STAMP)
	rm -rf build/docs-src && mkdir -p build && cp -r docs build/docs-src
	$(BIN)/python -m sphinx -b html -q -W --keep-going build/docs-src build/docs
	@echo "documentation: build/docs/index.html"

bench: $(STAMP) toolchain
	$(BIN)/python benchmarks/bench_engine.py
	$(BIN)/python benchmarks/bench_m4.py

# Side by side with motulator (issue 4): installs motulator into its own venv
# (benchmarks/.motulator-venv), never into .venv; see benchmarks/README.md.
.PHONY: bench-motulator
bench-motulator: $(STAMP)
	$(BIN)/python benchmarks/vs_motulator.py --out benchmarks/results

clean:
	rm -rf build $(VENV) $(OUT)
