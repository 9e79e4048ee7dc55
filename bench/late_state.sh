#!/usr/bin/env bash
# What a long run's state costs per image (issue 39), in minutes instead of the hours a long run
# takes: the same IMAGES new generated images (places no map has seen) are run twice,
#   fresh  on a new map;
#   late   after resuming a copy of MAP (e.g. the time.db bench/scale.sh leaves in OUT), so that
#          LTM, the map file and the word ids are those of the long run.
# Prints, per run, the medians of images 1,000 on (the dictionary at its ceiling in both) and the
# CPU each thread took per image over the same images (/proc; threads are named memloop-<role>),
# then their ratio late / fresh, and each run's peak RSS. The map is copied: MAP itself is not
# changed, unless IN_PLACE=1 (a scratch map too large to copy, e.g. bench/pad_map.py's).
# Usage: bench/late_state.sh MAP [IMAGES]
# Environment: BUILD_DIR=build, TTIME_MS=67 (the fresh run's T_time; the late run has its map's),
# SEED=99 (of the new images), OUT=folder to keep the CSVs in (default: a temporary one).
set -euo pipefail
cd "$(dirname "$0")/.."
map=${1:?usage: bench/late_state.sh MAP [IMAGES]}
images=${2:-3000}
build=${BUILD_DIR:-build}
out=${OUT:-$(mktemp -d)}
[ -f "$map" ] || { echo "late_state.sh: $map: no such map" >&2; exit 1; }
[ "$images" -ge 2000 ] || { echo "late_state.sh: IMAGES must be at least 2000" >&2; exit 1; }
mkdir -p "$out"
held=$("$build/memloop" inspect "$map" | sed -n 's/^images: \([0-9]*\).*/\1/p')
[ -n "$held" ] || { echo "late_state.sh: $map: cannot read its image count" >&2; exit 1; }

echo "machine: $(lscpu | sed -n 's/^Model name: *//p'), $(nproc) cores; $(date -u +%Y-%m-%d); memloop $(git rev-parse --short HEAD 2>/dev/null || echo '?')"
echo "map: $map ($held images); $images new images (memloop generate --seed ${SEED:-99})"

rm -rf "$out/new" "$out/after_map"
"$build/memloop" generate "$out/new" --seed "${SEED:-99}" --places $((images / 10)) \
  --revisit-every 0 >/dev/null
# The late run's input: the map's images (never read: resuming skips them), then the new ones.
# (One process makes them: a map of 200,000 images is as many links.)
python3 - "$out" "$held" "$images" <<'PY'
import os, sys
out, held, images = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
os.makedirs(f"{out}/after_map")
for i in range(1, held + 1):
    os.symlink(f"{out}/new/images/1.png", f"{out}/after_map/{i}.png")
for i in range(1, images + 1):
    os.symlink(f"{out}/new/images/{i}.png", f"{out}/after_map/{held + i}.png")
PY

# CPU (user + system, clock ticks) of each live thread of `pid`, by name, and of the whole process;
# the bytes it read and wrote through system calls (the map file, its log).
threads_cpu() {
  echo "process $(awk '{print $14 + $15}' "/proc/$1/stat")"
  echo "peak_rss_kb $(awk '$1 == "VmHWM:" {print $2}' "/proc/$1/status")"
  awk '$1 == "rchar:" {print "bytes_read", $2} $1 == "wchar:" {print "bytes_written", $2}' \
    "/proc/$1/io"
  for task in /proc/"$1"/task/*; do
    local ticks
    ticks=$(awk '{print $14 + $15}' "$task/stat" 2>/dev/null) && echo "$(cat "$task/comm") $ticks"
  done
}

run() {  # name args...
  local name=$1
  shift
  rm -f "$out/$name.csv"
  "$build/memloop" run "$@" --out "$out/$name.csv" >"$out/$name.txt" 2>&1 &
  local pid=$!
  local rows=0
  while [ "$rows" -lt 1000 ]; do
    sleep 0.2
    rows=$([ -f "$out/$name.csv" ] && echo $(($(wc -l <"$out/$name.csv") - 1)) || echo 0)
    kill -0 "$pid" 2>/dev/null || { cat "$out/$name.txt" >&2; exit 1; }
  done
  { echo "rows $rows $(date +%s.%N)"; threads_cpu "$pid"; } >"$out/$name.cpu0"
  while [ "$rows" -lt $((images - 100)) ]; do
    sleep 0.2
    rows=$(($(wc -l <"$out/$name.csv") - 1))
  done
  { echo "rows $rows $(date +%s.%N)"; threads_cpu "$pid"; } >"$out/$name.cpu1"
  wait "$pid"
}

run fresh "$out/new/images" --db "$out/fresh.db" --set memory.time_limit_ms="${TTIME_MS:-67}"
rm -f "$out"/fresh.db*
if [ "${IN_PLACE:-0}" = 1 ]; then
  run late "$out/after_map" --db "$map" --resume
else
  cp "$map" "$out/late.db"
  run late "$out/after_map" --db "$out/late.db" --resume
  rm -f "$out"/late.db*
fi

python3 - "$out" <<'PY'
import csv, statistics, sys
from collections import defaultdict
out = sys.argv[1]
ticks_ms = 10.0  # USER_HZ = 100

def cpu(name):
    def read(path):
        rows, wall, by = 0, 0.0, defaultdict(int)
        for line in open(path):
            key, *values = line.split()
            if key == 'rows':
                rows, wall = int(values[0]), float(values[1])
            else:
                by[key] += int(values[0])
        return rows, wall, by
    r0, w0, a = read(f'{out}/{name}.cpu0')
    r1, w1, b = read(f'{out}/{name}.cpu1')
    n = r1 - r0
    peak_rss_mb = b.pop('peak_rss_kb') / 1024  # a level, not a count: the one at the end
    per = {k: (b[k] - a.get(k, 0)) * ticks_ms / n for k in b}
    return per, (w1 - w0) * 1000 / n, peak_rss_mb

stages = ['iteration_ms', 'signature_ms', 'wm_stages_ms', 'retrieval_ms', 'checkpoint_ms',
          'cpu_ms']
wm_stages = ('likelihood_ms', 'filter_ms', 'selection_ms')  # those that walk WM
medians, cpus = {}, {}
for name in ('fresh', 'late'):
    rows = list(csv.DictReader(open(f'{out}/{name}.csv')))[1000:]
    for r in rows:
        r['wm_stages_ms'] = sum(float(r[k] or 0) for k in wm_stages)
    medians[name] = {k: statistics.median(float(r[k] or 0) for r in rows) for k in stages}
    cpus[name] = cpu(name)
io = ('bytes_read', 'bytes_written')
threads = sorted({k for n in cpus for k in cpus[n][0] if k != 'process' and k not in io},
                 key=lambda k: -cpus['late'][0].get(k, 0))
print()
print('| run | ' + ' | '.join(k.replace('_ms', '') for k in stages) +
      ' | wall / image | process CPU / image | ' + ' | '.join(threads) +
      ' | KB read / image | KB written / image | peak RSS MB |')
print('| --- |' + ' ---: |' * (len(stages) + 5 + len(threads)))
for name in ('fresh', 'late'):
    per, wall, rss = cpus[name]
    print(f'| {name} | ' + ' | '.join(f'{medians[name][k]:.2f}' for k in stages) +
          f' | {wall:.2f} | {per["process"]:.2f} | ' +
          ' | '.join(f'{per.get(k, 0):.2f}' for k in threads) + ' | ' +
          ' | '.join(f'{per[k] / ticks_ms / 1024:.0f}' for k in io) + f' | {rss:.0f} |')
ratio = lambda a, b: f'{b / a:.2f}x' if a > 0 else '-'
print('| late / fresh | ' + ' | '.join(ratio(medians['fresh'][k], medians['late'][k]) for k in stages) +
      f' | {ratio(cpus["fresh"][1], cpus["late"][1])} | ' +
      f'{ratio(cpus["fresh"][0]["process"], cpus["late"][0]["process"])} | ' +
      ' | '.join(ratio(cpus['fresh'][0].get(k, 0), cpus['late'][0].get(k, 0))
                 for k in threads + list(io)) +
      f' | {ratio(cpus["fresh"][2], cpus["late"][2])} |')
print()
print('medians of images 1,000 on (ms); CPU per image (ms, user + system) over the same images;'
      ' threads by name (memloop: the detector)')
PY
