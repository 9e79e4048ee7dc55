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

# The Gardens Point sets are two walks (their READMEs: images 0001-0100, then 0101-0200), mapped
# as a robot maps two walks: the first, then the second as a new session of its map (run
# --new-session). The whole-image channel weighs an earlier session's places only
# (filter.whole_image_scope).
declare -A second_walk_from=([gp_walk_a]=101 [gp_daynight_a]=101)

# Folders $out/walk1 and $out/walk2 of links to the images of data set $1 before and from image $2.
split_walks() {
  rm -rf "$out/walk1" "$out/walk2"
  mkdir "$out/walk1" "$out/walk2"
  local n=0 file
  for file in $(ls "$datasets/$1/images" | sort); do
    n=$((n + 1))
    ln -s "$(realpath "$datasets/$1/images/$file")" "$out/walk$([ $n -lt "$2" ] && echo 1 || echo 2)/$file"
  done
}

row() {  # dataset preset features budget
  local name=$1 preset=$2 feature=$3 budget=$4 csv="$out/run.csv"
  local run=("$build/memloop" run --set memory.time_limit_ms=0 --set features.type="$feature"
    --set memory.max_wm_locations="$budget" ${sets[@]+--set "${sets[@]}"} --db "$out/map.db")
  if [ -n "${second_walk_from[$name]:-}" ]; then
    split_walks "$name" "${second_walk_from[$name]}"
    "${run[@]}" "$out/walk1" --preset "$preset" --out "$out/walk1.csv" >/dev/null
    "${run[@]}" "$out/walk2" --new-session --out "$out/walk2.csv" >/dev/null
    { cat "$out/walk1.csv"; tail -n +2 "$out/walk2.csv"; } >"$csv"
  else
    "${run[@]}" "$datasets/$name/images" --preset "$preset" --out "$csv" >/dev/null
  fi
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
