# The two commands of the README:
#   make run   installs what is missing, builds Release, renders the default scene
#   make test  installs what is missing, builds, checks formatting, runs every test
BUILD ?= build
JOBS ?= $(shell nproc)
MULTIRAY = $(BUILD)/src/app/multiray

.PHONY: run test deps build format check-format bench sanitize clean

deps:
	@scripts/install-deps.sh

build: deps
	@mkdir -p $(BUILD)
	cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=Release > $(BUILD)/configure.log 2>&1 || (cat $(BUILD)/configure.log; false)
	cmake --build $(BUILD) -j$(JOBS)

run: build
	$(MULTIRAY) render --res 640x360 --spp 16 --out out
	@echo "multiray: wrote out/frame_0000.png and out/stats.json"

check-format:
	@scripts/check-format.sh

test: build check-format
	cd $(BUILD) && ctest --output-on-failure -j$(JOBS) --timeout 600

format:
	clang-format -i $$(git ls-files '*.h' '*.cpp')

bench: build
	$(BUILD)/bench/bench_throughput

# ASan + UBSan build of everything, tests run under it.
sanitize: deps
	cmake --preset sanitize > /dev/null
	cmake --build --preset sanitize -j$(JOBS)
	ctest --preset sanitize -j$(JOBS)

clean:
	rm -rf $(BUILD) build-* out
