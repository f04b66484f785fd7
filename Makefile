# SPDX-License-Identifier: AGPL-3.0-or-later
# palpa — the two commands of the README, plus a few conveniences.
#   make demo    install Debian packages if missing, build the command line (Release),
#                run the subject pipeline (workflow/Snakefile) on the bundled synthetic
#                subject (examples/subject): poke logs -> fits -> body -> rest -> design
#                -> report; prints where the report is. Rerun after an interruption:
#                it goes on where it stopped.
#   make test    install, build, run the whole suite, every test once: the unit tests
#                in the sanitizer build, then the physics and command-line tests in the
#                Release build (ends with ctest's summary)
#   make python  build the Python module into build/release/python (use it with
#                PYTHONPATH=build/release/python /usr/bin/python3)
#   make bench   build (Release) and run the benchmarks, one JSON line per figure
#   make fuzz    build the libFuzzer programs (preset fuzz) and run each for
#                FUZZ_SECONDS (default 60); findings go to build/fuzz/fuzz/artifacts
# Repeated calls rebuild incrementally.

JOBS ?= $(shell nproc 2>/dev/null || echo 2)
FUZZ_SECONDS ?= 60
DEMO_OUT ?= demo-out
DEMO_SUBJECT ?= examples/subject/subject.json

.PHONY: all setup build python demo test test-release test-asan bench fuzz clean

all: build

setup:
	@bash scripts/setup.sh

# The command line alone: what `make demo` runs.
build: setup
	cmake --preset release >/dev/null
	cmake --build --preset release -j $(JOBS) --target palpa_cli

python: setup
	cmake --preset release >/dev/null
	cmake --build --preset release -j $(JOBS) --target python

demo: build
	@snakemake -s workflow/Snakefile --cores $(JOBS) --unlock --config subjects=$(DEMO_SUBJECT) \
	    out=$(DEMO_OUT) palpa=$(CURDIR)/build/release/apps/palpa/palpa >/dev/null 2>&1 || true
	snakemake -s workflow/Snakefile --cores $(JOBS) --rerun-incomplete --config subjects=$(DEMO_SUBJECT) \
	    out=$(DEMO_OUT) palpa=$(CURDIR)/build/release/apps/palpa/palpa

test-asan: setup
	cmake --preset asan >/dev/null
	cmake --build --preset asan -j $(JOBS)
	ctest --preset asan -j $(JOBS)

test-release: setup
	cmake --preset release >/dev/null
	cmake --build --preset release -j $(JOBS)
	ctest --preset release -j $(JOBS)

# The sanitizer pass runs first so that the output ends with the summary of the
# full Release suite.
test: setup
	$(MAKE) --no-print-directory test-asan
	$(MAKE) --no-print-directory test-release

bench: build
	cmake --build --preset release -j $(JOBS) --target palpa_benchmarks
	bash bench/run.sh build/release

fuzz: setup
	cmake --preset fuzz >/dev/null
	cmake --build --preset fuzz -j $(JOBS)
	bash fuzz/run.sh build/fuzz $(FUZZ_SECONDS)

clean:
	rm -rf build
