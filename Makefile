# The two commands a new user runs are `make demo` and `make test` (README). Both install the
# Debian packages that are missing, configure and build first.
BUILD_DIR ?= build
JOBS ?= $(shell nproc)
DEMO_OUT ?= demo_out

.PHONY: all deps configure build test demo bench format clean

all: build

deps:
	@bash scripts/install_deps.sh

configure: deps
	@if [ ! -f $(BUILD_DIR)/CMakeCache.txt ]; then \
	  generator="Unix Makefiles"; command -v ninja >/dev/null && generator=Ninja; \
	  cmake -S . -B $(BUILD_DIR) -G "$$generator" -DCMAKE_BUILD_TYPE=Release; \
	fi

build: configure
	cmake --build $(BUILD_DIR) -j$(JOBS)

test: build
	cd $(BUILD_DIR) && ctest --output-on-failure -j$(JOBS)

# Simulates a short stretch of the 16-inch steel pipe of Hansen et al. (2010), and evaluates the
# shipped estimate of a 2 m out-and-back run against its ground truth.
demo: build
	@mkdir -p $(DEMO_OUT)
	./$(BUILD_DIR)/pipescope simulate --preset steel-16in --frames 240 --out $(DEMO_OUT)/steel-16in
	./$(BUILD_DIR)/pipescope odometry $(DEMO_OUT)/steel-16in --method dense-unrolled \
	  --out $(DEMO_OUT)/run
	@echo "Results: simulated dataset in $(DEMO_OUT)/steel-16in (images/, groundtruth.tum, dataset.yaml)"
	@echo "         odometry run in $(DEMO_OUT)/run (trajectory.tum, mosaic.png, run.json, metrics.json)"

bench: build
	@bash bench/run_kernels.sh $(BUILD_DIR)

format:
	find src bench -name '*.h' -o -name '*.cc' | xargs clang-format -i

clean:
	rm -rf $(BUILD_DIR) $(DEMO_OUT)
