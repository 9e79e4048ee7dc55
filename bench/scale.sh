#!/usr/bin/env bash
# Scale (issue 9): a long generated sequence of distinct places with revisits of places last seen
# MIN_AGE+ images before (only retrieval from LTM can find them), run three ways:
#   time   T_time set (default: 2x the steady median iteration, measured first on images 2000-3000
#          of a run under the WM budget);
#   budget a WM budget of BUDGET locations, T_time off (repeatable);
#   off    memory management off (no T_time, no budget), stopped after OFF_SECONDS: the baseline
#          that grows.
# Prints, per run, one row per block of 1000 images (median and max iteration ms, WM size,
# dictionary size, RSS), then the run's totals; writes the time plot (the paper's Fig. 4) as
# $OUT/scale-time.png (PLOT=docs/scale-time.png for the docs' figure). Frames are rendered on the
# fly (memloop demo --places): nothing on disk but the maps and CSVs.
# Usage: bench/scale.sh [PLACES] > docs/scale-run.md
# Environment: RUNS="time budget off", TTIME_MS, BUDGET=500, MIN_AGE=10000, OFF_SECONDS=1800,
# BUILD_DIR=build, OUT=folder to keep the CSVs in (default: a temporary one), PLOT=the plot's path,
# SETS="name=value ..." given to every run (calibration included) after the run's own,
# REALTIME_PRIORITY=N: every run with --realtime-priority N, PACE_HZ=R: the T_time run with
# --pace R (a camera at R Hz; docs/cli.md).
set -euo pipefail
cd "$(dirname "$0")/.."
build=${BUILD_DIR:-build}
places=${1:-4550}  # 10 frames each, a revisit after every 10: about 50,000 images
runs=${RUNS:-time budget off}
budget=${BUDGET:-500}
min_age=${MIN_AGE:-10000}
off_seconds=${OFF_SECONDS:-1800}
out=${OUT:-$(mktemp -d)}
mkdir -p "$out"
sequence=(--places "$places" --frames-per-place 10 --revisit-every 10 --min-revisit-age "$min_age")

echo "machine: $(lscpu | sed -n 's/^Model name: *//p'), $(nproc) cores; $(date -u +%Y-%m-%d); memloop $(git rev-parse --short HEAD 2>/dev/null || echo '?')"
echo "sequence: memloop demo ${sequence[*]}"
[ -n "${SETS:-}" ] && echo "every run: --set $SETS"
[ -n "${REALTIME_PRIORITY:-}" ] && echo "every run: --realtime-priority $REALTIME_PRIORITY"
[ -n "${PACE_HZ:-}" ] && echo "the T_time run: --pace $PACE_HZ"

# One run: memloop demo with the given --set values; RSS sampled every second against the rows
# written so far, with the machine's steal time (/proc/stat, clock ticks: time a virtual machine's
# host ran something else while this machine wanted to run).
run() {  # name seconds(0 = no limit) sets...
  local name=$1 seconds=$2
  shift 2
  rm -f "$out/$name.db"*
  local limit=()
  [ "$seconds" != 0 ] && limit=(timeout --signal=KILL "$seconds")
  local extra=()
  [ -n "${SETS:-}" ] && read -r -a extra <<<"$SETS"
  local args=()
  [ -n "${REALTIME_PRIORITY:-}" ] && args=(--realtime-priority "$REALTIME_PRIORITY")
  [ "$name" = time ] && [ -n "${PACE_HZ:-}" ] && args+=(--pace "$PACE_HZ")
  "${limit[@]}" /usr/bin/time -f "%M" -o "$out/$name.peak" "$build/memloop" demo "${sequence[@]}" \
    "${args[@]}" --set "$@" "${extra[@]}" --db "$out/$name.db" --out "$out/$name.csv" >"$out/$name.txt" 2>/dev/null &
  local pid=$!
  : >"$out/$name.rss"
  while kill -0 "$pid" 2>/dev/null; do
    local child
    child=$(pgrep -n -f "memloop demo .*$out/$name.db" || true)
    if [ -n "$child" ] && [ -r "/proc/$child/status" ] && [ -f "$out/$name.csv" ]; then
      echo "$(($(wc -l <"$out/$name.csv") - 1)) $(awk '/VmRSS/ {print $2}' "/proc/$child/status")" \
        "$(awk '/^cpu / {print $9}' /proc/stat)" >>"$out/$name.rss" 2>/dev/null || true
    fi
    sleep 1
  done
  wait "$pid" || true
}

if [[ " $runs " == *" time "* ]] && [ -z "${TTIME_MS:-}" ]; then
  # The steady median with memory management on (the WM budget: transfers and retrievals
  # included), images 2000-3000; T_time is twice that. (The unbounded run's median is half as
  # much: without transfers and retrievals, a T_time from it is below an iteration's fixed cost.)
  saved=$places
  sequence[1]=300
  run calibrate 0 memory.time_limit_ms=0 memory.max_wm_locations="$budget"
  sequence[1]=$saved
  TTIME_MS=$(python3 -c "
import csv, statistics
t = [float(r['iteration_ms']) for r in csv.DictReader(open('$out/calibrate.csv'))][2000:3000]
print(round(2 * statistics.median(t)))")
  echo "T_time: 2 x the median of images 2000-3000 under the WM budget = $TTIME_MS ms"
fi

for name in $runs; do
  case $name in
    time) run time 0 memory.time_limit_ms="$TTIME_MS" ;;
    budget) run budget 0 memory.time_limit_ms=0 memory.max_wm_locations="$budget" ;;
    off) run off "$off_seconds" memory.time_limit_ms=0 ;;
  esac
  python3 bench/scale_summary.py "$name" "$out" "${TTIME_MS:-0}"
done

if [ -f "$out/time.csv" ]; then
  plot=${PLOT:-$out/scale-time.png}
  awk -F, 'NR > 1 {print $1, $16}' "$out/time.csv" >"$out/time.dat"
  gnuplot <<GP
set terminal pngcairo size 1000,380 font "sans,10"
set output "$plot"
set xlabel "image"
set ylabel "iteration time (ms)"
set logscale y
set key top left
plot "$out/time.dat" using 1:2 with dots lc rgb "#1f77b4" title "time per image", \
     $TTIME_MS with lines lw 2 lc rgb "#d62728" title "T_{time} = $TTIME_MS ms"
GP
  echo
  echo "plot: $plot"
fi
