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

# Simulates 8 s of the 16-inch steel pipe of Hansen et al. (2010), runs dense odometry on the
# unrolled wall, places three example observations and writes report.html (pipescope demo).
demo: build
	./$(BUILD_DIR)/pipescope demo --out $(DEMO_OUT)

bench: build
	@bash bench/run_kernels.sh $(BUILD_DIR)

format:
	find src bench -name '*.h' -o -name '*.cc' | xargs clang-format -i

clean:
	rm -rf $(BUILD_DIR) $(DEMO_OUT)
