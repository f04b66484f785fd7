# palpa — the two commands of the README, plus a few conveniences.
#   make demo    install Debian packages if missing, build (Release), run `palpa demo`
#   make test    install, build, run the whole suite: sanitizer build over the unit
#                tests, then the Release build over everything (ends with ctest's summary)
#   make bench   build (Release) and run the benchmarks, one JSON line per figure
# Repeated calls rebuild incrementally.

JOBS ?= $(shell nproc 2>/dev/null || echo 2)
DEMO_OUT ?= demo-out

.PHONY: all setup build demo test test-release test-asan bench clean

all: build

setup:
	@bash scripts/setup.sh

build: setup
	cmake --preset release >/dev/null
	cmake --build --preset release -j $(JOBS)

demo: build
	./build/release/apps/palpa/palpa demo --out $(DEMO_OUT)

test-asan: setup
	cmake --preset asan >/dev/null
	cmake --build --preset asan -j $(JOBS)
	ctest --preset asan -j $(JOBS)

test-release: build
	ctest --preset release -j $(JOBS)

# The sanitizer pass runs first so that the output ends with the summary of the
# full Release suite.
test: setup
	$(MAKE) --no-print-directory test-asan
	$(MAKE) --no-print-directory test-release

bench: build
	cmake --build --preset release -j $(JOBS) --target palpa_benchmarks
	bash bench/run.sh build/release

clean:
	rm -rf build
