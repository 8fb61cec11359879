# predvs — top-level convenience targets. Each target does the set-up it needs.
BUILD_DIR ?= build
BUILD_TYPE ?= Release
JOBS ?= $(shell nproc)
PREDVS := $(BUILD_DIR)/app/predvs

.PHONY: deps configure build run test bench golden clean

deps:
	@bash scripts/install-deps.sh

configure: deps
	@cmake -S . -B $(BUILD_DIR) -DCMAKE_BUILD_TYPE=$(BUILD_TYPE) -DPREDVS_BUILD_TESTS=ON -DPREDVS_BUILD_BENCHMARKS=ON >/dev/null

build: configure
	@cmake --build $(BUILD_DIR) -j $(JOBS)

# The main job: the default scenario (IBVS on a moving target, 2-frame vision delay),
# comparing no prediction (hold) with kf-cv and cs-akf-adaptive.
run: build
	$(PREDVS) servo

test: build
	cd $(BUILD_DIR) && ctest --output-on-failure -j $(JOBS)

bench: build
	$(BUILD_DIR)/bench/predvs_bench --benchmark_counters_tabular=true

# Regenerates the golden trace of the default scenario (see tests/servo).
golden: build
	$(PREDVS) servo --out $(BUILD_DIR)/golden-run --no-plots
	cp $(BUILD_DIR)/golden-run/log.csv data/golden/ibvs-moving-target.csv

clean:
	rm -rf $(BUILD_DIR) out
