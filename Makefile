# isoforge: the two commands a new user needs are `make demo` and `make test`.
# Both install missing Debian packages first (apt-get; via sudo when not root), then configure
# and build in Release mode with CMake, then run.
#
#   make demo     build, then convert data/ (out/demo/) and make the chapter's figures
#                 (out/figures/index.html: datasets, .glb, pictures, numbers)
#   make test     build, then run the unit tests, CLI tests, consumer-package test and the quick
#                 verification subset (ctest)
#   make verify   the full accuracy verification suite (CGAL), report in out/verify/
#   make bench    benchmarks against the peers (verify/bench/)
#   make fuzz     build the libFuzzer targets with clang and run each for FUZZ_SECONDS
#   make sanitize the ctest suite built with AddressSanitizer + UndefinedBehaviorSanitizer
#                 (clang, static library) in build-sanitize/, which make fuzz shares; any finding
#                 fails. The CGAL verification suite (verify/) is left out there: it runs in
#                 make test, and its three CGAL translation units and decimation cases would
#                 take a quarter of CI's 45 minutes under the sanitizers; so is the headless
#                 browser test (a minute of Chromium; the sanitized HTTP server it talks to is
#                 tested by cli_gltf_view) and cli_examples (every --help and README example:
#                 4.5 minutes under the sanitizers; the commands' own CLI tests run there)
#   make install  install into PREFIX (default /usr/local); the installed programs find the
#                 library through a relative RPATH, so the prefix can be moved
#
# .ci/run runs make test, make fuzz and make sanitize.

BUILD       ?= build
BENCH_BUILD ?= build-bench
SANITIZE_BUILD ?= build-sanitize
PREFIX      ?= /usr/local
JOBS        ?= $(shell nproc 2>/dev/null || echo 2)
FUZZ_SECONDS ?= 20
GENERATOR   := $(shell command -v ninja >/dev/null 2>&1 && echo Ninja || echo "Unix Makefiles")

# Debian 12 packages the build, tests, verification and benchmarks need.
DEBIAN_PACKAGES := cmake ninja-build g++ make ccache pkg-config git \
  libcgal-dev libgmp-dev libmpfr-dev \
  libopenvdb-dev libboost-iostreams-dev libtbb-dev \
  libceres-dev libeigen3-dev \
  libdraco-dev \
  libcli11-dev libfmt-dev libpugixml-dev zlib1g-dev libdeflate-dev liblz4-dev liblzma-dev \
  libgtest-dev libgmock-dev libbenchmark-dev \
  python3 python3-vtk9 python3-numpy libmeshoptimizer-dev \
  clang libclang-rt-14-dev chromium draco

.PHONY: all deps configure build demo test verify bench fuzz sanitize install clean

all: build

deps:
	@missing=""; \
	for p in $(DEBIAN_PACKAGES); do \
	  dpkg-query -W -f='$${Status}' $$p 2>/dev/null | grep -q "install ok installed" || missing="$$missing $$p"; \
	done; \
	if [ -n "$$missing" ]; then \
	  echo "installing missing Debian packages:$$missing"; \
	  if [ "$$(id -u)" -eq 0 ]; then SUDO=""; else SUDO="sudo"; fi; \
	  $$SUDO apt-get update -q && \
	  DEBIAN_FRONTEND=noninteractive $$SUDO apt-get install -y -q --no-install-recommends $$missing; \
	fi
	@# Node.js and npm (the viewer's three.js, the glTF validator, playwright-core): Debian's
	@# when missing; then the npm packages of viewer/package-lock.json when missing or stale.
	@if ! command -v node >/dev/null 2>&1 || ! command -v npm >/dev/null 2>&1; then \
	  echo "installing Node.js and npm (Debian packages)"; \
	  if [ "$$(id -u)" -eq 0 ]; then SUDO=""; else SUDO="sudo"; fi; \
	  $$SUDO apt-get update -q && \
	  DEBIAN_FRONTEND=noninteractive $$SUDO apt-get install -y -q --no-install-recommends nodejs npm; \
	fi
	@if [ ! -f viewer/node_modules/.package-lock.json ] || \
	    [ viewer/package-lock.json -nt viewer/node_modules/.package-lock.json ]; then \
	  echo "installing the viewer's npm packages (npm ci in viewer/)"; \
	  cd viewer && npm ci --no-audit --no-fund; \
	fi

configure: deps
	@if [ ! -f $(BUILD)/CMakeCache.txt ]; then \
	  cmake -S . -B $(BUILD) -G "$(GENERATOR)" -DCMAKE_BUILD_TYPE=Release; \
	fi

build: configure
	cmake --build $(BUILD) -j $(JOBS)

# Every file in data/ read, described and converted to VTK XML under out/demo/ (open those in
# ParaView); then the chapter's figures (docs/figures.md): datasets, .glb, PNG pictures and
# out/figures/index.html, with a summary table.
DEMO_INPUTS := data/hello.vtk data/fran_cut.vtk data/Torso.vtp data/bunny.ply data/ironProt.vtk \
  data/office.binary.vtk data/post.vtk data/blow.vtk data/headsq/quarter.nhdr \
  data/HeadMRVolume.mhd
demo: build
	@mkdir -p out/demo
	@set -e; for f in $(DEMO_INPUTS); do \
	  echo "==== $$f"; \
	  $(BUILD)/src/isoforge info $$f; \
	  $(BUILD)/src/isoforge convert $$f out/demo/$$(basename $${f%.*}) --vtk-xml; \
	done; \
	echo "==== data/combxyz.bin + data/combq.bin (PLOT3D combustor)"; \
	$(BUILD)/src/isoforge info data/combxyz.bin --q data/combq.bin; \
	$(BUILD)/src/isoforge convert data/combxyz.bin --q data/combq.bin out/demo/combustor --vtk-xml
	$(BUILD)/src/isoforge contour data/headsq/quarter.nhdr -v 1150 --flip --largest -o out/demo/head_skin.vtp
	@echo "==== the chapter's figures (out/figures/index.html; 'isoforge view out/figures' for the viewer)"
	$(BUILD)/src/isoforge figures --out out/figures

test: build
	cd $(BUILD) && ctest --output-on-failure -j $(JOBS) --timeout 900

verify: build
	$(BUILD)/verify/isoforge-verify --all --report out/verify

bench: deps
	cmake -S . -B $(BENCH_BUILD) -G "$(GENERATOR)" -DCMAKE_BUILD_TYPE=Release \
	  -DISOFORGE_BUILD_BENCH=ON -DISOFORGE_BUILD_TESTS=OFF
	cmake --build $(BENCH_BUILD) -j $(JOBS)
	./verify/bench/run.sh $(BENCH_BUILD) out/bench

# make fuzz and make sanitize share one clang build with AddressSanitizer and
# UndefinedBehaviorSanitizer (RelWithDebInfo with line tables only, static library): the library
# is compiled with sanitizers once. Clang: its sanitizer builds compile about twice as fast as
# GCC's here. Static library: one build of it serves every test (consumer_package then tests the
# static package). Unity build: the library and the CLI are unity batches of 8 sources in every
# build (ISOFORGE_UNITY_BUILD, CMakeLists.txt); CMAKE_UNITY_BUILD here batches the tests' and
# fuzzers' sources as well.
SANITIZE_CONFIGURE := CXX=clang++ cmake -S . -B $(SANITIZE_BUILD) -G "$(GENERATOR)" \
  -DCMAKE_BUILD_TYPE=RelWithDebInfo "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O2 -gline-tables-only -DNDEBUG" \
  -DISOFORGE_SANITIZE=address,undefined -DISOFORGE_BUILD_FUZZERS=ON -DBUILD_SHARED_LIBS=OFF \
  -DISOFORGE_BUILD_VERIFY=OFF -DCMAKE_UNITY_BUILD=ON

fuzz: deps
	$(SANITIZE_CONFIGURE)
	cmake --build $(SANITIZE_BUILD) -j $(JOBS) --target fuzzers isoforge_cli
	./tests/fuzz/run.sh $(SANITIZE_BUILD) $(FUZZ_SECONDS)

# detect_leaks: LeakSanitizer too; print_stacktrace: where UBSan findings come from.
sanitize: deps
	$(SANITIZE_CONFIGURE)
	cmake --build $(SANITIZE_BUILD) -j $(JOBS)
	cd $(SANITIZE_BUILD) && ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 \
	  ctest --output-on-failure -j $(JOBS) --timeout 1800 -E '^(viewer_browser|cli_examples)$$'

install: build
	cmake --install $(BUILD) --prefix $(PREFIX)

clean:
	rm -rf $(BUILD) $(BUILD)-consumer-static $(BENCH_BUILD) $(SANITIZE_BUILD) out
