# Two entry points, both safe on a fresh Debian machine:
#   make run   installs what is missing, builds (Release) and runs the main job
#   make test  installs what is missing, builds and runs every test with ctest
BUILD_DIR ?= build
JOBS ?= $(shell nproc 2>/dev/null || echo 2)
SCENE ?= scenes/rocky_mockup.yaml
OUT ?= out

.PHONY: run test check test-arm test-sanitize test-tsan fuzz soak deps configure build bench bench-instructions bench-compare clean

# The main job: the walking robot on the rocky mock-up with the URG-04LX
# (mixed pixels simulated, the paper's scan filters), with its pose-error
# sweep (which replays the main walk's scans); about 11 s of CPU. It builds only the tool:
# the tests and benchmarks are `make test`'s and `make bench`'s business.
run: configure
	cmake --build $(BUILD_DIR) -j $(JOBS) --target stridemap_cli
	$(BUILD_DIR)/bin/stridemap experiment rocky-walk --sensor urg --scene $(SCENE) --mixed-pixels on --out $(OUT) --seed 1

# The tests that mostly wait (label waits) run in a lane of their own beside
# the rest (tools/ctest-lanes.sh). The sanitizer stages run theirs in line:
# there only LiveCrash waits, and their real-time tests have less headroom.
test: build
	@bash tools/ctest-lanes.sh $(BUILD_DIR) $(JOBS)

# What CI runs (.ci/run), in a fresh clone of HEAD, each stage's wall time
# printed at the end (tools/check.sh; docs/reliability.md, "The check's time").
# Start it in the background: `make check > check.out 2>&1 &`.
check:
	@bash tools/check.sh

deps:
	@bash tools/install-deps.sh

configure: deps
	cmake -S . -B $(BUILD_DIR) -DCMAKE_BUILD_TYPE=Release

build: configure
	cmake --build $(BUILD_DIR) -j $(JOBS)

# The whole suite again under AddressSanitizer + UndefinedBehaviorSanitizer
# (clang); any report fails the run. The install test is left out: it builds
# an unsanitized consumer against the sanitized libraries, and so is the
# Python module (an extension under ASan needs the runtime preloaded into
# python3). The parsing layers are also instrumented for libFuzzer's coverage, so
# `make fuzz` reuses this build instead of compiling everything a fourth time
# (docs/reliability.md). The browser test (label browser) is left out too:
# it runs Chromium and Node.js, which are not built with the sanitizers, on
# a page the unsanitized `make test` already checks.
SAN_DIR ?= build-sanitize
SAN_FLAGS = -fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer
# UBSan's checks are emitted before the optimiser runs, so Eigen's small
# expression functions look too big to inline: the clang default left about
# a hundred of them as calls per matrix product, and experiment tests ran
# twice as long (docs/reliability.md, "Build choices"). A higher threshold
# inlines them again; every check stays.
SAN_INLINE = -mllvm -inline-threshold=1000
# CMake passes the compile flags to the link too, where clang says the
# inliner's option went unused, once per library and program.
SAN_LINK_QUIET = -Wno-unused-command-line-argument
# ... but not in the test programs' own code nor the tool's command files,
# where it made each unity batch compile 45-70 % longer (a core test batch:
# 52 s of CPU against 30 s; the tool 66 s against 46 s) and the work they
# drive runs in the libraries: LLVM's default threshold there, at -O1 as in
# the other builds (docs/reliability.md, "Build choices").
SAN_GLUE_OPTIMIZATION = -DSTRIDEMAP_GLUE_OPTIMIZATION="-O1;SHELL:-mllvm -inline-threshold=225"
# Line tables are all a sanitizer report needs for file:line stacks; full
# debug info made every compile and link of these builds slower. -O2, not
# -O1: at -O1 the ASan + UBSan build took about 3 min less but its tests
# about twice as long (docs/reliability.md, "The check's time").
# ROS is left out of both sanitizer stages (-DSTRIDEMAP_WITH_ROS=OFF): Debian's
# ROS 1 libraries are not instrumented, and its tests need roscore, a Python
# process (docs/ros.md); `make test` runs them (ctest label ros).
# No precompiled headers in the two clang builds: Debian's ccache 4.7 keeps
# clang's absolute -include-pch path in its key, so in a fresh clone every
# precompiled header and every file that uses one missed the cache.
SAN_OPT_LEVEL ?= -O2
SAN_OPT_FLAGS = -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="$(SAN_OPT_LEVEL) -gline-tables-only -DNDEBUG" -DSTRIDEMAP_WITH_ROS=OFF \
	  -DSTRIDEMAP_PRECOMPILED_HEADERS=OFF
SAN_CONFIGURE = CC=clang CXX=clang++ cmake -S . -B $(SAN_DIR) -DCMAKE_BUILD_TYPE=RelWithDebInfo $(SAN_OPT_FLAGS) $(SAN_GLUE_OPTIMIZATION) \
	  -DSTRIDEMAP_BUILD_BENCHMARKS=OFF -DSTRIDEMAP_BUILD_PYTHON=OFF -DSTRIDEMAP_BUILD_FUZZERS=ON -DCMAKE_CXX_FLAGS="$(SAN_FLAGS) $(SAN_INLINE)" \
	  -DCMAKE_EXE_LINKER_FLAGS="$(SAN_FLAGS) $(SAN_LINK_QUIET)" -DCMAKE_SHARED_LINKER_FLAGS="$(SAN_FLAGS) $(SAN_LINK_QUIET)"
test-sanitize: deps
	$(SAN_CONFIGURE)
	cmake --build $(SAN_DIR) -j $(JOBS)
	cd $(SAN_DIR) && ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
	  ctest --output-on-failure -j $(JOBS) -E install_and_find_package -LE browser

# The embedded build (docs/install.md, "Embedded build"): the layers that
# need Eigen alone (core, sensors, preprocess, pipeline, sim) cross-compiled
# for 64-bit ARM with Debian's crossbuild-essential-arm64, and their tests
# (labels core, sensors, preprocess, pipeline) run under qemu-aarch64.
# GoogleTest is compiled for arm64 from Debian's /usr/src/googletest, so no
# arm64 package comes from apt (tools/install-arm-deps.sh). The layering
# probes are left out: they run the build tool, not an ARM program, and
# `make test` runs them.
ARM_DIR ?= build-arm64
test-arm:
	@bash tools/install-arm-deps.sh
	cmake -S . -B $(ARM_DIR) --toolchain $(CURDIR)/cmake/aarch64-linux-gnu.cmake -DCMAKE_BUILD_TYPE=Release \
	  -DSTRIDEMAP_CORE_LAYERS_ONLY=ON -DSTRIDEMAP_GTEST_SOURCE_DIR=/usr/src/googletest
	cmake --build $(ARM_DIR) -j $(JOBS)
	cd $(ARM_DIR) && ctest --output-on-failure -j $(JOBS) -L '^(core|sensors|preprocess|pipeline)$$'

# Reliability (docs/reliability.md). The test programs that run threads
# under ThreadSanitizer (clang); any report fails the run. Those are the
# layers whose code or tests start threads: core (MapPublisher), pipeline,
# live (the emulator and the live loop), experiments (the soak's planner
# thread) and cli (live runs of the tool, itself built with TSan). The other
# layers' programs are single-threaded, so TSan has nothing to check there
# and they are not built (nor is the browser test, label browser: Chromium
# is not built with TSan). OpenCV's TBB threads are invisible to TSan;
# tools/tsan.supp says why.
TSAN_DIR ?= build-tsan
TSAN_FLAGS = -fsanitize=thread -fno-omit-frame-pointer
TSAN_LAYERS = core pipeline live experiments cli
# Layers whose code runs on one thread only (configuring fails if one starts
# a thread): compiled without TSan's instrumentation, which made the
# experiments under it several times slower and could find nothing there.
TSAN_UNINSTRUMENTED = sensors preprocess sim io config render mapfile recordings devices vision
# TSan clears the shadow of a freed block over 64 kB by unmapping it, and the
# next block there faults its pages back in one by one: the maps the
# experiments copy made page faults half the TSan stage's time. Clearing
# with memset keeps the pages.
TSAN_SHADOW = clear_shadow_mmap_threshold=1073741824
test-tsan: deps
	CC=clang CXX=clang++ cmake -S . -B $(TSAN_DIR) -DCMAKE_BUILD_TYPE=RelWithDebInfo $(SAN_OPT_FLAGS) \
	  -DSTRIDEMAP_TSAN_UNINSTRUMENTED_LAYERS="$(subst $(eval) ,;,$(strip $(TSAN_UNINSTRUMENTED)))" \
	  -DSTRIDEMAP_BUILD_BENCHMARKS=OFF -DSTRIDEMAP_BUILD_PYTHON=OFF -DCMAKE_CXX_FLAGS="$(TSAN_FLAGS)" \
	  -DCMAKE_EXE_LINKER_FLAGS="$(TSAN_FLAGS)" -DCMAKE_SHARED_LINKER_FLAGS="$(TSAN_FLAGS)" \
	  -DSTRIDEMAP_TEST_TARGET_LAYERS="$(subst $(eval) ,;,$(strip $(TSAN_LAYERS)))"
	cmake --build $(TSAN_DIR) -j $(JOBS) --target stridemap_layer_tests
	cd $(TSAN_DIR) && TSAN_OPTIONS=halt_on_error=1:second_deadlock_stack=1:suppressions=$(CURDIR)/tools/tsan.supp:$(TSAN_SHADOW) \
	  ctest --output-on-failure -j $(JOBS) -L '^($(subst $(eval) ,|,$(strip $(TSAN_LAYERS))))$$'

# Every libFuzzer target of fuzz/ for FUZZ_SECONDS each, FUZZ_JOBS at a time
# (clang, ASan + UBSan, in the sanitizer build); a crash fails the run and
# leaves its input in $(SAN_DIR)/fuzz-artifacts/. FUZZ_SEED=N makes the
# inputs tried the same on every run (CI sets it; fuzz/run.sh says why).
FUZZ_SECONDS ?= 30
FUZZ_JOBS ?= $(JOBS)
FUZZ_SEED ?=
FUZZ_TARGETS ?=
fuzz: deps
	$(SAN_CONFIGURE)
	cmake --build $(SAN_DIR) -j $(JOBS) --target stridemap_fuzzers
	FUZZ_JOBS=$(FUZZ_JOBS) FUZZ_SEED=$(FUZZ_SEED) bash fuzz/run.sh $(SAN_DIR) $(FUZZ_SECONDS) $(FUZZ_TARGETS)

# The full soak: SOAK_SCANS simulated scans over a path far larger than the
# map, run twice with the same seed; fails on growing memory, an invalid
# cell, a lost scan or results that differ between the runs.
SOAK_SCANS ?= 100000
soak: build
	$(BUILD_DIR)/bin/stridemap soak --scans $(SOAK_SCANS) --seed 1 --repeat 2 --out $(OUT)
	$(BUILD_DIR)/bin/stridemap soak --motion walk --scans $(SOAK_SCANS) --seed 1 --repeat 2 --out $(OUT)/walk

bench: build
	@bash tools/run-benchmarks.sh $(BUILD_DIR)

# Instructions per valid point of the per-point path (callgrind over a fixed
# workload; docs/performance.md). Needs valgrind.
bench-instructions: configure
	cmake --build $(BUILD_DIR) -j $(JOBS) --target point_path_workload
	@bash tools/bench-instructions.sh $(BUILD_DIR)

# stridemap against OctoMap and a plain per-point update on the same
# simulated scans (bench/compare.cpp, docs/performance.md), then the replay
# throughput of `map --log` and `map --bag` (tools/replay_throughput.py).
# OctoMap is a bench-only dependency, installed here rather than by
# `make deps`, so that CI does not pay for it.
bench-compare: configure
	@dpkg -s liboctomap-dev >/dev/null 2>&1 || { echo "installing liboctomap-dev (bench-compare only)"; \
	  if [ "$$(id -u)" = 0 ]; then apt-get install -y --no-install-recommends liboctomap-dev; \
	  else sudo apt-get install -y --no-install-recommends liboctomap-dev; fi; }
	cmake -S . -B $(BUILD_DIR)
	cmake --build $(BUILD_DIR) -j $(JOBS) --target stridemap_bench_compare
	$(BUILD_DIR)/bin/compare $(CURDIR)
	@echo; echo "Replay, one core:"; echo
	/usr/bin/python3 tools/replay_throughput.py --tool $(BUILD_DIR)/bin/stridemap

clean:
	rm -rf $(BUILD_DIR) $(OUT)
