#!/usr/bin/env bash
# The paper's Table 1 (Sec. IV) on its own data set, Lip6Outdoor, for both presets. Columns:
#   T_time = inf;  WM budget 280 and 102 (the max WM of the paper's 1.4 s and 0.4 s columns: the
#   deterministic analogue, since this machine is ~20x faster than 2011's);  a real T_time in the
#   place of each of the paper's two: for 1.4 s, over the 99th percentile of the iterations at
#   T_time = inf, as the paper's 1.4 s was over its 1.34 s maximum (WM is never cut); for 0.4 s,
#   the median iteration of the T_time = inf run while WM held 92-112 locations (or its largest
#   WM, if smaller), so that WM settles near the paper's 102 (both divided by the preset's memory.time_target, at which
#   transfer starts). Real T_time depends on the machine and its load: run it alone.
# Rows: images, max WM, max dictionary, max iteration time, precision at T_loop, recall at 100%
# precision strict (ignored pairs neither true nor false) and lenient (`--ignored-as-true`, the
# protocol of the paper's 2011 scripts).
# Usage: bench/paper_table.sh [IMAGES_DIR GROUND_TRUTH] > table.md
# Environment: PRESETS="default paper2011", BUILD_DIR=build, SETS="name=value ..." (every run).
set -euo pipefail
cd "$(dirname "$0")/.."
build=${BUILD_DIR:-build}
images=${1:-../shared/datasets/lip6_outdoor/images}
truth=${2:-../shared/datasets/lip6_outdoor/ground_truth.bmp}
presets=${PRESETS:-default paper2011}
read -r -a sets <<<"${SETS:-}"
if [ ! -d "$images" ]; then
  echo "paper_table.sh: $images is absent (the data sets ship beside the project): nothing to run" >&2
  exit 0
fi
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT

run() {  # preset column --set...
  local preset=$1 column=$2
  shift 2
  "$build/memloop" run "$images" --preset "$preset" "$@" ${sets[@]+--set "${sets[@]}"} \
    --db "$out/map.db" --out "$out/$preset.$column.csv" >/dev/null
  rm -f "$out"/map.db*
  "$build/memloop" eval "$out/$preset.$column.csv" "$truth" --json >"$out/$preset.$column.json"
  "$build/memloop" eval "$out/$preset.$column.csv" "$truth" --json --ignored-as-true \
    >"$out/$preset.$column.lenient.json"
}
field() {  # json-file key: the value of key, at the top level or in table1
  python3 -c 'import json,sys; d=json.load(open(sys.argv[1])); t=d["table1"]; print({**d, **t}[sys.argv[2]])' "$1" "$2"
}

echo "Data set: $images, ground truth $truth"
echo "Machine: $(lscpu | sed -n 's/^Model name: *//p'), $(nproc) cores; $(date -u +%Y-%m-%d); memloop $(git rev-parse --short HEAD 2>/dev/null || echo '?')${SETS:+; --set $SETS}"
for preset in $presets; do
  run "$preset" inf --set memory.time_limit_ms=0
  run "$preset" wm280 --set memory.time_limit_ms=0 --set memory.max_wm_locations=280
  run "$preset" wm102 --set memory.time_limit_ms=0 --set memory.max_wm_locations=102
  target=$([ "$preset" = paper2011 ] && echo 1 || echo 0.75)  # memory.time_target
  read -r slow fast < <(python3 -c '
import csv, statistics, sys
rows = list(csv.DictReader(open(sys.argv[1])))
times = sorted(float(r["iteration_ms"]) for r in rows)
wm = min(102, max(int(r["wm_size"]) for r in rows))  # a smaller set never reaches 102
at_102 = [float(r["iteration_ms"]) for r in rows if abs(int(r["wm_size"]) - wm) <= 10]
target = float(sys.argv[2])
print(round(1.045 * times[int(0.99 * (len(times) - 1))] / target, 1),
      round(statistics.median(at_102) / target, 1))' "$out/$preset.inf.csv" "$target")
  run "$preset" tslow --set memory.time_limit_ms="$slow"
  run "$preset" tfast --set memory.time_limit_ms="$fast"
  columns=(inf wm280 wm102 tslow tfast)
  echo
  echo "### --preset $preset"
  echo
  echo "| | T_time = inf | WM budget 280 | WM budget 102 | T_time = $slow ms (for 1.4 s) | T_time = $fast ms (for 0.4 s) |"
  echo "| --- | ---: | ---: | ---: | ---: | ---: |"
  row() {  # label key format [lenient]
    printf "| %s |" "$1"
    for c in "${columns[@]}"; do
      local file="$out/$preset.$c${4:+.lenient}.json"
      printf " $3 |" "$(python3 -c 'import sys; print(float(sys.argv[1]) * float(sys.argv[2]))' "$(field "$file" "$2")" "${5:-1}")"
    done
    echo
  }
  row "# images" images "%.0f"
  row "Max WM size (locations)" max_wm_size "%.0f"
  row "Max dictionary size (words)" max_dictionary_size "%.0f"
  row "Max iteration time (s)" max_iteration_s "%.3f"
  row "Precision at T_loop (%)" precision_percent "%.1f"
  row "Recall at T_loop, strict (%)" recall_percent "%.1f"
  row "Recall at 100% precision, strict (%)" recall_at_100_precision "%.1f" "" 100
  row "Recall at 100% precision, lenient (%)" recall_at_100_precision "%.1f" lenient 100
done
echo
echo "The paper (its Table 1, Lip6Outdoor; its own labels, lenient): T_time = inf / 1.4 s / 0.4 s:"
echo "max WM 280 / 280 / 102, max dictionary 89k / 89k / 31k words, max iteration 1.34 / 1.34 /"
echo "0.51 s, precision 100%, recall 77% / 77% / 81%."
