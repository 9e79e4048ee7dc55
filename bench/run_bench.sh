#!/usr/bin/env bash
# Whole runs and kernels, on this machine. Prints the machine, the kernel medians (Google
# Benchmark, 5 repetitions) and, for whole runs, the median and max iteration time and the
# largest WM and dictionary, from the per-image CSV. Compare numbers of one run of this script.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${BUILD_DIR:-build}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT

echo "machine: $(lscpu | sed -n 's/^Model name: *//p'), $(nproc) cores, $(uname -sr)"
"$build/bench/memloop_benchmarks" --benchmark_repetitions=5 --benchmark_report_aggregates_only \
  --benchmark_filter="${BENCH_FILTER:-.}" 2>/dev/null | grep -E "median|Benchmark|^-"

column() {  # csv name -> 1-based index of the column so named
  head -1 "$1" | tr ',' '\n' | grep -nx "$2" | cut -d: -f1
}

summarize() {  # name csv
  local time_column wm_column words_column match_column times n
  time_column=$(column "$2" iteration_ms)
  wm_column=$(column "$2" wm_size)
  words_column=$(column "$2" dictionary_size)
  match_column=$(column "$2" matched_image)
  times=$(tail -n +2 "$2" | cut -d, -f"$time_column" | sort -g)
  n=$(echo "$times" | wc -l)
  awk -F, -v name="$1" -v n="$n" -v median="$(echo "$times" | sed -n "$(((n + 1) / 2))p")" \
      -v max="$(echo "$times" | tail -1)" -v w="$wm_column" -v d="$words_column" -v m="$match_column" \
    'NR > 1 { if ($w > wm) wm = $w; if ($d > words) words = $d; if ($m != "") loops++ }
     END { printf "%-36s images %4d  loops %4d  median %6.1f ms  max %6.1f ms  max WM %4d  max words %6d\n",
       name, n, loops, median, max, wm, words }' "$2"
}

echo
echo "Whole runs (memloop demo: the generated route, 260 images of 320x240):"
for setting in "memory.time_limit_ms=0" "memory.max_wm_locations=35" "memory.time_limit_ms=10"; do
  "$build/memloop" demo --set "$setting" --out "$out/demo.csv" >/dev/null
  summarize "demo $setting" "$out/demo.csv"
done
samples=../shared/datasets/rtabmap_samples/images
if [ -d "$samples" ]; then
  echo "Whole runs ($samples, 84 images of 512x384):"
  for setting in "memory.time_limit_ms=0" "memory.time_limit_ms=20"; do
    "$build/memloop" run "$samples" --set "$setting" --out "$out/samples.csv" >/dev/null
    summarize "rtabmap_samples $setting" "$out/samples.csv"
  done
else
  echo "($samples absent: real-data runs skipped)"
fi
