#!/usr/bin/env bash
# The paper's experiment (Sec. IV, Table 1) on one data set: runs it at T_time = infinity, at the
# paper's guideline for its image rate (200-400 ms under the image period: 0.7 s at 1 Hz), and at
# a smaller T_time, evaluates each run against the ground truth and prints Table 1 in Markdown.
# Usage: bench/paper_table.sh [IMAGES_DIR GROUND_TRUTH IMAGE_RATE_HZ SMALL_T_TIME_S]
# Default: ../shared/datasets/rtabmap_samples at 1 Hz, small T_time 0.025 s (its iterations take
# about 16 ms: a smaller T_time empties WM).
set -euo pipefail
cd "$(dirname "$0")/.."
build=${BUILD_DIR:-build}
images=${1:-../shared/datasets/rtabmap_samples/images}
truth=${2:-../shared/datasets/rtabmap_samples/ground_truth.bmp}
rate=${3:-1}
small=${4:-0.025}
[ -d "$images" ] || { echo "paper_table: $images: no such folder" >&2; exit 1; }
guideline=$(awk -v r="$rate" 'BEGIN { printf "%.3g", 1 / r - 0.3 }')  # 300 ms under the period
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT

declare -a columns=("inf" "$guideline" "$small")
for t in "${columns[@]}"; do
  ms=$([ "$t" = inf ] && echo 0 || awk -v t="$t" 'BEGIN { print t * 1000 }')
  "$build/memloop" run "$images" --set memory.time_limit_ms="$ms" --out "$out/$t.csv" >/dev/null
  "$build/memloop" eval "$out/$t.csv" "$truth" --json >"$out/$t.json"
done

field() { grep -o "\"$2\": [0-9.e+-]*" "$out/$1.json" | head -1 | awk '{ print $2 }'; }
echo "Data set: $images ($(field inf images) images, ${rate} Hz), ground truth $truth"
echo "Machine: $(lscpu | sed -n 's/^Model name: *//p'), $(nproc) cores; features: SURF (default)"
echo
printf "| | T_time = inf | T_time = %s s (guideline) | T_time = %s s |\n" "$guideline" "$small"
echo "| --- | --- | --- | --- |"
row() {  # label field format
  printf "| %s |" "$1"
  for t in "${columns[@]}"; do printf " $3 |" "$(field "$t" "$2")"; done
  echo
}
row "# images" images "%s"
row "Max WM size (locations)" max_wm_size "%s"
row "Max dictionary size (words)" max_dictionary_size "%s"
row "Max iteration time (s)" max_iteration_s "%.3f"
row "Precision (%)" precision_percent "%.0f"
row "Recall (%)" recall_percent "%.1f"
printf "| Recall at 100%% precision (%%) |"
for t in "${columns[@]}"; do printf " %.1f |" "$(awk -v r="$(field "$t" recall_at_100_precision)" 'BEGIN { print 100 * r }')"; done
echo
