#!/usr/bin/env bash
# Installs memloop from BUILD_DIR into a temporary prefix, then configures, builds and runs the
# consumer project (tests/consumer) against it, as a user's own project would.
# Usage: install_test.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
build=$1
source=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cmake --install "$build" --prefix "$work/prefix" >/dev/null
config=$(find "$work/prefix" -name memloopConfig.cmake)
[ -n "$config" ] || { echo "no memloopConfig.cmake installed"; exit 1; }
[ -f "$work/prefix/include/memloop/detector.h" ] || { echo "headers not installed"; exit 1; }
cmake -S "$source/tests/consumer" -B "$work/build" -DCMAKE_PREFIX_PATH="$work/prefix" \
  -DCMAKE_BUILD_TYPE=Release >"$work/configure.log" 2>&1 || { cat "$work/configure.log"; exit 1; }
cmake --build "$work/build" >"$work/build.log" 2>&1 || { cat "$work/build.log"; exit 1; }
# The core target links what detection needs, not the evaluation's libmatio.
if grep -q matio "$work/build/CMakeFiles/consumer.dir/link.txt"; then
  echo "memloop::memloop pulls in libmatio:"; cat "$work/build/CMakeFiles/consumer.dir/link.txt"
  exit 1
fi
"$work/build/consumer" "$work/map.db"

# The Python module, installed where Debian's python3 finds a prefix's modules.
module=$(find "$work/prefix" -name 'memloop*.so' -path '*dist-packages*')
[ -n "$module" ] || { echo "the Python module is not installed"; exit 1; }
PYTHONPATH=$(dirname "$module") /usr/bin/python3 -c \
  "import memloop; assert any(p['name'] == 'memory.stm_size' for p in memloop.parameters())" \
  || { echo "the installed Python module does not import"; exit 1; }
echo "python module: $module"

# As a subproject: configured only (building would compile memloop again); no test or benchmark.
cmake -S "$source/tests/consumer" -B "$work/sub" -DMEMLOOP_SOURCE_DIR="$source" \
  >"$work/sub.log" 2>&1 || { cat "$work/sub.log"; exit 1; }
if [ -d "$work/sub/memloop/tests" ] || [ -d "$work/sub/memloop/bench" ]; then
  echo "memloop as a subproject builds its tests or benchmarks"; exit 1
fi
echo "subproject: no tests, no benchmarks"
