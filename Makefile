# The two commands of the README:
#   make run   installs what is missing, builds Release, renders the default scene
#   make test  installs what is missing, builds, checks formatting, runs every test (the
#              fuzz targets' seed corpora replayed among them)
BUILD ?= build
JOBS ?= $(shell nproc)
MULTIRAY = $(BUILD)/src/app/multiray

FUZZ_SECONDS ?= 60
# Warnings are errors on Debian 12, the platform whose compiler and packaged headers the
# build is kept warning-free on (docs/testing.md); elsewhere a newer compiler's new
# warnings must not stop a build. WERROR=ON|OFF overrides.
WERROR ?= $(shell . /etc/os-release 2>/dev/null && [ "$$VERSION_CODENAME" = bookworm ] && echo ON || echo OFF)

.PHONY: run test deps build format check-format bench sanitize fuzz fuzz-smoke clean

deps:
	@scripts/install-deps.sh

# Unity batches of 8 source files: a fresh build spends most of its time parsing the same
# headers (CLI11, nlohmann/json, GoogleTest, Embree) again for every file (docs/testing.md).
build: deps
	@mkdir -p $(BUILD)
	cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=Release -DMULTIRAY_WERROR=$(WERROR) -DCMAKE_UNITY_BUILD=ON -DCMAKE_UNITY_BUILD_BATCH_SIZE=8 > $(BUILD)/configure.log 2>&1 || (cat $(BUILD)/configure.log; false)
	cmake --build $(BUILD) -j$(JOBS)

# The default render on every device that helps (--devices auto), then, where this machine
# has an OpenCL device, the same frame split between a CPU core and it, with the picture of
# the split (out/pair_split.png) and the balance summary.
run: build
	@$(MULTIRAY) render --res 640x360 --spp 16 --out out/frame.png --overlay -q
	@echo "multiray: wrote out/frame.png, out/frame_split.png and out/frame.stats.json"
	@if $(MULTIRAY) devices | grep -q '^ *opencl:0:'; then \
	  $(MULTIRAY) render --res 640x360 --spp 16 --out out/pair.png --overlay \
	    --devices cpu:threads=1:cores=0,opencl:0:cores=1; fi

check-format: deps
	@scripts/check-format.sh

# Every test, among them FuzzReplay.<target>: each fuzz target run once on every input of
# its seed corpus, built by the Release build (fuzz/README.md). The libFuzzer runs are not
# part of it: their clang build alone took about 150 s on a fresh clone (docs/testing.md).
test: check-format build
	cd $(BUILD) && ctest --output-on-failure -j$(JOBS) --timeout 600

# A 3-second libFuzzer run of each fuzz target from its seeds (clang-15, -O0, ASan + UBSan,
# in build-fuzz-smoke/; skipped with a message when clang-15 is missing).
fuzz-smoke: deps
	@JOBS=$(JOBS) fuzz/run.sh smoke

format:
	clang-format -i $$(git ls-files '*.h' '*.cpp')

bench: build
	cmake --build $(BUILD) --target multiray_bench -j$(JOBS)
	$(BUILD)/bench/bench_throughput

# ASan + UBSan build of everything, tests run under it (the fuzz replays too).
sanitize: deps
	cmake --preset sanitize > /dev/null
	cmake --build --preset sanitize -j$(JOBS)
	ctest --preset sanitize -j$(JOBS)

# libFuzzer targets (clang-15, build-fuzz/), each run FUZZ_SECONDS; findings are kept in
# fuzz/crashes/. FUZZ_TARGETS="ply obj" picks targets; FUZZ_KNOWN=1 also reports the
# known open findings (docs/reliability.md).
fuzz: deps
	@JOBS=$(JOBS) FUZZ_SECONDS=$(FUZZ_SECONDS) FUZZ_KNOWN=$(FUZZ_KNOWN) fuzz/run.sh long

clean:
	rm -rf $(BUILD) build-* out
