#!/usr/bin/env bash
# Recall on the real sequences of ../shared/datasets (each with a ground_truth.bmp), as issue 8
# asks: one table, one row per (data set, preset, features, WM budget). Budgets are 50% and 25%
# of the unbounded run's max WM; "lenient" is recall @100% P with a match on the ignored band of an
# image with a loop counted as found (memloop eval --ignored-as-true, the paper's 2011 protocol).
# T_time is off in every row (repeatable: the same input gives the same table on any machine; only
# the times differ). Usage:
#   bench/real_data.sh [DATASETS_DIR] > table.md     (default ../shared/datasets)
# Environment: PRESETS="default paper2011 hand-held", FEATURES="surf sift orb", BUILD_DIR=build,
# SETS="name=value ..." (more parameters for every row, e.g. to measure a change of default).
set -euo pipefail
cd "$(dirname "$0")/.."
build=${BUILD_DIR:-build}
datasets=${1:-../shared/datasets}
presets=${PRESETS:-default paper2011 hand-held}
features=${FEATURES:-surf sift orb}
read -r -a sets <<<"${SETS:-}"
if [ ! -d "$datasets" ]; then
  echo "real_data.sh: $datasets is absent (the data sets ship beside the project): nothing to run" >&2
  exit 0
fi
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT

echo "machine: $(lscpu | sed -n 's/^Model name: *//p'), $(nproc) cores; $(date -u +%Y-%m-%d); memloop $(git rev-parse --short HEAD 2>/dev/null || echo '?')${SETS:+; --set $SETS}"
echo
echo "| data set | preset | features | WM budget | recall @100% P | lenient | T_loop at it | precision @T_loop | recall @T_loop | false pos. | median ms | max ms | max WM |"
echo "| --- | --- | --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |"

row() {  # dataset preset features budget
  local name=$1 preset=$2 feature=$3 budget=$4 csv="$out/run.csv"
  "$build/memloop" run "$datasets/$name/images" --preset "$preset" --set memory.time_limit_ms=0 \
    --set features.type="$feature" --set memory.max_wm_locations="$budget" \
    ${sets[@]+--set "${sets[@]}"} \
    --db "$out/map.db" --out "$csv" >/dev/null
  rm -f "$out"/map.db*
  "$build/memloop" eval "$csv" "$datasets/$name/ground_truth.bmp" --json >"$out/eval.json"
  "$build/memloop" eval "$csv" "$datasets/$name/ground_truth.bmp" --json --ignored-as-true \
    >"$out/lenient.json"
  python3 - "$name" "$preset" "$feature" "$budget" "$csv" "$out/eval.json" "$out/lenient.json" <<'PY'
import csv, json, statistics, sys
name, preset, feature, budget, path, evaluation, lenient = sys.argv[1:8]
e = json.load(open(evaluation))
lenient = json.load(open(lenient))["recall_at_100_precision"]
rows = list(csv.DictReader(open(path)))
times = [float(r["iteration_ms"]) for r in rows]
a = e["loop_closures"]
print(f"| {name} | {preset} | {feature} | {budget if budget != '0' else 'none'} | "
      f"{100 * e['recall_at_100_precision']:.1f}% | {100 * lenient:.1f}% | "
      f"{e['threshold_at_100_precision']:.3f} | "
      f"{100 * e['precision']:.1f}% | {100 * e['recall']:.1f}% | {a['false_positives']} | "
      f"{statistics.median(times):.1f} | {max(times):.1f} | {e['table1']['max_wm_size']} |")
print(e["table1"]["max_wm_size"], file=open(evaluation + ".max_wm", "w"))
PY
}

for dir in "$datasets"/*/; do
  name=$(basename "$dir")
  [ -f "$dir/ground_truth.bmp" ] && [ -d "$dir/images" ] || continue
  for preset in $presets; do
    for feature in $features; do
      row "$name" "$preset" "$feature" 0
      max_wm=$(cat "$out/eval.json.max_wm")
      for percent in 50 25; do
        budget=$(( max_wm * percent / 100 ))
        [ "$budget" -ge 1 ] || budget=1
        row "$name" "$preset" "$feature" "$budget"
      done
    done
  done
done
