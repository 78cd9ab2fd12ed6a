# sdftrace — the two Quick-start commands:
#   make demo   install what is missing, build, render the default scene
#   make test   install what is missing, build with sanitizers, run every test
#               (bench-quick's pipeline included, as the ctest bench_quick)
#   make bench  the study: regenerate bench/results/ (bakes, table, figures)
#               and Keinert's techniques against the paper; commits nothing.
#               make bench-quick: the same, small, checked.
#   make docs   rewrite the pages made from the code (docs/mesh-settings.md)
#   make fuzz   build the fuzz harnesses (tests/fuzz) with clang's libFuzzer in
#               build-fuzz/ and run each FUZZ_SECONDS (default 600); pick
#               them with FUZZ_TARGETS (default: vdb nvdb mesh scene npy)
# and, for using sdftrace as a library:
#   make install PREFIX=/opt/sdftrace   build (Release) and install there
# Debian packages live in one list: .ci/debian-packages.

PACKAGES := $(shell cat .ci/debian-packages)
JOBS ?= $(shell nproc)
PREFIX ?= /usr/local

.PHONY: all deps build demo test install docs bench bench-quick fuzz clean

all: build

deps:
	@missing=$$(for p in $(PACKAGES); do dpkg-query -W -f='$${Status}\n' $$p 2>/dev/null | grep -q '^install ok installed' || echo $$p; done); \
	if [ -n "$$missing" ]; then \
	  echo "installing:" $$missing; \
	  if [ "$$(id -u)" -ne 0 ]; then SUDO=sudo; fi; \
	  $$SUDO apt-get update -qq && DEBIAN_FRONTEND=noninteractive $$SUDO apt-get install -y -qq --no-install-recommends $$missing; \
	fi

build: deps
	cmake -S . -B build -DCMAKE_BUILD_TYPE=Release
	cmake --build build -j $(JOBS)

demo: build
	@mkdir -p out
	./build/sdftrace render --scene temple -o out/temple.exr --png out/temple.png
	@echo "wrote out/temple.exr and out/temple.png"

test: deps
	cmake -S . -B build-test -DCMAKE_BUILD_TYPE=RelWithDebInfo -DSDFT_SANITIZE=ON -DSDFT_WERROR=ON
	cmake --build build-test -j $(JOBS)
	cd build-test && ctest --output-on-failure -j $(JOBS)

install: build
	cmake --install build --prefix $(PREFIX)

# The pages made from the code: docs/mesh-settings.md from the mesh
# component's tables of settings (make test checks it is current).
docs: build
	./build/mesh_settings_table docs/mesh-settings.md

bench: build
	./bench/study.sh
	./bench/keinert.sh

bench-quick: build
	./bench/study.sh --quick

# Each harness grows its corpus in build-fuzz/corpus/NAME from the seeds
# (tests/fuzz/corpus/NAME) and the regressions (tests/fuzz/regressions/NAME);
# what crashes or hangs lands in build-fuzz/findings/NAME/ and stops the run.
# Readers run in a child process (src/common/isolated_read.h): there a loop
# is stopped after 0.5 s, and one allocation over 512 MiB is a finding here
# (ASan's limit, which ends a child at once), not libFuzzer's malloc limit,
# which children would trip too.
# Minimize it and keep it, so that make test replays it:
#   build-fuzz/tests/fuzz/fuzz_NAME -minimize_crash=1 -runs=20000 \
#     -exact_artifact_path=tests/fuzz/regressions/NAME/WHAT build-fuzz/findings/NAME/crash-...
FUZZ_SECONDS ?= 600
FUZZ_TARGETS ?= vdb nvdb mesh scene npy

fuzz: deps
	CC=clang CXX=clang++ cmake -S . -B build-fuzz -DCMAKE_BUILD_TYPE=RelWithDebInfo -DSDFT_FUZZ=ON
	cmake --build build-fuzz -j $(JOBS) --target $(addprefix fuzz_,$(FUZZ_TARGETS))
	@for t in $(FUZZ_TARGETS); do \
	  mkdir -p build-fuzz/corpus/$$t build-fuzz/findings/$$t; \
	  echo "fuzz_$$t: $(FUZZ_SECONDS) s"; \
	  ASAN_OPTIONS=symbolize=0:max_allocation_size_mb=512 SDFT_READ_TIME_LIMIT=0.5 \
	  ./build-fuzz/tests/fuzz/fuzz_$$t build-fuzz/corpus/$$t tests/fuzz/corpus/$$t tests/fuzz/regressions/$$t \
	    -max_total_time=$(FUZZ_SECONDS) -timeout=60 -rss_limit_mb=4096 -malloc_limit_mb=1048576 \
	    -print_final_stats=1 -artifact_prefix=build-fuzz/findings/$$t/ || exit 1; \
	done

clean:
	rm -rf build build-test build-fuzz out
