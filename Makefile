# The two commands of the README, for a fresh Debian 12 machine:
#   make demo   installs what is missing, builds the library and CLI (Release), runs the demo
#   make test   installs what is missing (ROS 1 too), builds, runs every test through ctest
BUILD_DIR ?= build
JOBS ?= $(shell nproc)
PACKAGES := cmake g++ make pkg-config libopencv-dev libflann-dev libboost-dev liblz4-dev libsqlite3-dev \
            libcli11-dev libspdlog-dev libfmt-dev nlohmann-json3-dev libgtest-dev libgmock-dev \
            libbenchmark-dev libmatio-dev gnuplot-nox pybind11-dev python3-dev python3-numpy \
            librosbag-storage-dev libsensor-msgs-dev libcpp-httplib-dev libpq-dev
# Only the tests need a browser (they open `memloop report` and `memloop view` in headless
# Chromium; python3-websocket drives the viewer through its DevTools protocol), pytest and
# cv2 (the Python module's tests read images as a user's script does), Ceres (the pose-graph
# example the tests build and run), PostgreSQL's server (the fleet's tests start their own).
TEST_PACKAGES := chromium python3-websocket python3-pytest python3-opencv libceres-dev postgresql-15
# The ROS 1 node (ros/, docs/ros.md) and its tests' roscore: Debian's ROS packages. Without
# them everything else builds; the node is not.
ROS_PACKAGES := libroscpp-dev libimage-transport-dev libmessage-filters-dev libdiagnostic-msgs-dev \
                libstd-srvs-dev libgeometry-msgs-dev libstd-msgs-dev ros-std-msgs ros-geometry-msgs \
                python3-gencpp python3-genpy python3-geometry-msgs ros-core
# bench/tight_time.sh's PAUSES needs oslat (the machine's own pauses); bench/ros_live.sh rospy's
# diagnostics messages and cv2.
BENCH_PACKAGES := rt-tests python3-diagnostic-msgs python3-sensor-msgs python3-opencv

.PHONY: all deps test-deps ros-deps bench-deps install-packages configure build demo test bench docs format clean

all: build

# Installs only the Debian packages that are missing (idempotent; root or sudo).
deps:
	@$(MAKE) --no-print-directory install-packages WANTED="$(PACKAGES)"

test-deps:
	@$(MAKE) --no-print-directory install-packages WANTED="$(TEST_PACKAGES)"

ros-deps:
	@$(MAKE) --no-print-directory install-packages WANTED="$(ROS_PACKAGES)"

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

# ROS first: the node is configured and built only when its packages are there.
test: ros-deps test-deps build
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
