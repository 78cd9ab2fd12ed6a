# sdftrace — the two Quick-start commands:
#   make demo   install what is missing, build, render the default scene
#   make test   install what is missing, build with sanitizers, run every test
#               (bench-quick's pipeline included, as the ctest bench_quick)
#   make bench  the study: regenerate bench/results/ (bakes, table, figures)
#               and Keinert's techniques against the paper; commits nothing. make bench-quick: the same, small, checked.
# and, for using sdftrace as a library:
#   make install PREFIX=/opt/sdftrace   build (Release) and install there
# Debian packages live in one list: .ci/debian-packages.

PACKAGES := $(shell cat .ci/debian-packages)
JOBS ?= $(shell nproc)
PREFIX ?= /usr/local

.PHONY: all deps build demo test install bench bench-quick clean

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

bench: build
	./bench/study.sh
	./bench/keinert.sh

bench-quick: build
	./bench/study.sh --quick

clean:
	rm -rf build build-test out
