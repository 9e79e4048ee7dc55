# The two commands of the README, for a fresh Debian 12 machine:
#   make demo   installs what is missing, builds the library and CLI (Release), runs the demo
#   make test   installs what is missing, builds, runs every test through ctest
BUILD_DIR ?= build
JOBS ?= $(shell nproc)
PACKAGES := cmake g++ make pkg-config libopencv-dev libflann-dev libboost-dev liblz4-dev libsqlite3-dev \
            libcli11-dev libspdlog-dev libfmt-dev nlohmann-json3-dev libgtest-dev libgmock-dev \
            libbenchmark-dev libmatio-dev gnuplot-nox pybind11-dev python3-dev python3-numpy \
            librosbag-storage-dev libsensor-msgs-dev
# Only the tests need a browser (they open `memloop report` in headless Chromium), pytest and
# cv2 (the Python module's tests read images as a user's script does).
TEST_PACKAGES := chromium python3-pytest python3-opencv
# Only bench/tight_time.sh's PAUSES needs oslat (the machine's own pauses).
BENCH_PACKAGES := rt-tests

.PHONY: all deps test-deps bench-deps install-packages configure build demo test bench docs format clean

all: build

# Installs only the Debian packages that are missing (idempotent; root or sudo).
deps:
	@$(MAKE) --no-print-directory install-packages WANTED="$(PACKAGES)"

test-deps:
	@$(MAKE) --no-print-directory install-packages WANTED="$(TEST_PACKAGES)"

bench-deps:
	@$(MAKE) --no-print-directory install-packages WANTED="$(BENCH_PACKAGES)"

install-packages:
	@missing=""; for package in $(WANTED); do \
	  dpkg-query -W -f='$${Status}' $$package 2>/dev/null | grep -q "install ok installed" \
	    || missing="$$missing $$package"; \
	done; \
	if [ -n "$$missing" ]; then \
	  echo "Installing Debian packages:$$missing"; \
	  if [ "$$(id -u)" -eq 0 ]; then sudo=""; else sudo="sudo"; fi; \
	  $$sudo apt-get update -qq && \
	  DEBIAN_FRONTEND=noninteractive $$sudo apt-get install -y -qq $$missing >/dev/null; \
	fi

configure: deps
	cmake -S . -B $(BUILD_DIR) -DCMAKE_BUILD_TYPE=Release -DMEMLOOP_BUILD_TESTS=ON \
	  -DMEMLOOP_BUILD_BENCHMARKS=ON >/dev/null

build: configure
	cmake --build $(BUILD_DIR) -j$(JOBS)

# The library and the command-line tool only: no test or benchmark is built.
demo: configure
	cmake --build $(BUILD_DIR) -j$(JOBS) --target memloop_cli
	./$(BUILD_DIR)/memloop demo

test: build test-deps
	cd $(BUILD_DIR) && ctest --output-on-failure -j$(JOBS)

bench: build
	bench/run_bench.sh

# Regenerates docs/parameters.md from the parameter registry.
docs: build
	./$(BUILD_DIR)/memloop params --markdown > docs/parameters.md

format:
	clang-format -i $$(git ls-files '*.h' '*.cc')

clean:
	rm -rf $(BUILD_DIR)
