#!/usr/bin/env bash
# A robot's map on a PostgreSQL server against the SQLite file, on the same images (docs/fleet.md).
# Starts a private server (initdb and pg_ctl in a temporary folder, a Unix socket, no TCP port;
# as root it runs as the user postgres), then, T_time off, for each data set:
#   - one robot on the file, then on the server: per-image median and max, loop closures, wall time;
#   - THREE robots at once on the server (the same images, three roles of one fleet), then three
#     robots at once on three files: each one's per-image median, the wall time of all three;
#   - the rows the server wrote per second of its CPU (pg_stat_user_tables over the postmaster's).
# With PAD=N (e.g. PAD=10x5000), the fleet's tables first get N robots' worth of locations
# (copies of a real map's rows under other robots' names), so that the robot's retrievals read
# from a server holding them: ltm_read_ms per retrieved location is reported.
# Usage: bench/fleet.sh [IMAGE_FOLDER ...]   (default: ../shared/datasets/lip6_outdoor/images)
# Environment: BUILD_DIR=build, SETS="name=value ..." (more parameters), PAD=ROBOTSxLOCATIONS.
set -euo pipefail
cd "$(dirname "$0")/.."
memloop=$PWD/${BUILD_DIR:-build}/memloop
folders=("$@")
[ ${#folders[@]} -gt 0 ] || folders=(../shared/datasets/lip6_outdoor/images)
read -r -a extra <<<"${SETS:-}"
sets=(memory.time_limit_ms=0 "${extra[@]}")
source bench/private_server.sh
"$memloop" fleet init "postgresql://admin@/fleet?host=$work" --robot r1 --robot r2 --robot r3 >/dev/null
rows_written() { psql -d fleet -c "SELECT sum(n_tup_ins + n_tup_upd + n_tup_del) FROM pg_stat_user_tables"; }

# Median and max of iteration_ms, loop closures, and ltm_read_ms per retrieved location of a CSV.
summary() {
  /usr/bin/python3 - "$1" <<'PY'
import csv, statistics, sys
rows = list(csv.DictReader(open(sys.argv[1])))
times = [float(r["iteration_ms"]) for r in rows]
retrieved = sum(len(r["retrieved"].split(";")) for r in rows if r["retrieved"])
read = sum(float(r["ltm_read_ms"]) for r in rows)
per = f"{read / retrieved:.2f}" if retrieved else "-"
print(f"{statistics.median(times):.1f} | {max(times):.0f} | "
      f"{sum(1 for r in rows if r['matched_image'])} | {retrieved} | {per}")
PY
}

# Every row of robots r1..r3 goes (the owner's connection is not bound by row-level security).
clear_robots() {
  for table in $(psql -d fleet -c "SELECT tablename FROM pg_tables WHERE schemaname='memloop'"); do
    psql -d fleet -c "DELETE FROM memloop.$table WHERE robot IN ('r1', 'r2', 'r3')"
  done
}

if [ -n "${PAD:-}" ]; then
  robots=${PAD%x*}; locations=${PAD#*x}
  # A seed map's rows on the server (robot seed), copied under robots pad1..padN with location
  # and word ids shifted until each holds `locations` locations.
  psql -d fleet -c "CREATE ROLE seed LOGIN IN ROLE memloop_robots"
  "$memloop" run "${folders[0]}" --db "$uri" --robot seed --set "${sets[@]}" >/dev/null
  seed=$(psql -d fleet -c "SELECT count(*) FROM memloop.locations WHERE robot='seed'")
  for ((r = 1; r <= robots; ++r)); do
    for ((offset = 0; offset < locations; offset += seed)); do
      for table in locations:id signature_words:location_id location_images:location_id \
                   links:from_id words:id appearances:location_id; do
        name=${table%%:*}; key=${table#*:}
        columns=$(psql -d fleet -c "SELECT string_agg(column_name, ',') FROM information_schema.columns WHERE table_schema='memloop' AND table_name='$name' AND column_name NOT IN ('robot', '$key')")
        psql -d fleet -c "INSERT INTO memloop.$name(robot, $key, $columns) SELECT 'pad$r', $key + $offset * 1000, $columns FROM memloop.$name WHERE robot='seed'"
      done
    done
  done
  psql -d fleet -c "ANALYZE"
  echo "padded: $(psql -d fleet -c "SELECT count(*) FROM memloop.locations") locations of $(psql -d fleet -c "SELECT count(DISTINCT robot) FROM memloop.locations") robots on the server ($(psql -d fleet -c "SELECT pg_size_pretty(pg_database_size('fleet'))"))"
  echo
fi

echo "machine: $(lscpu | sed -n 's/^Model name: *//p'), $(nproc) cores; $(date -u +%Y-%m-%d); memloop $(git rev-parse --short HEAD 2>/dev/null || echo '?'); --set ${sets[*]}"
echo
echo "| images | map | robots at once | median ms | max ms | loop closures | retrieved | read ms per retrieved | wall s | server rows/s of its CPU |"
echo "| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |"
for folder in "${folders[@]}"; do
  name=$(basename "$(dirname "$folder")")
  rm -f "$work"/*.csv "$work"/*.db*
  clear_robots
  start=$(date +%s.%N)
  "$memloop" run "$folder" --db "$work/1.db" --out "$work/file.csv" --set "${sets[@]}" >/dev/null
  echo "| $name | file | 1 | $(summary "$work/file.csv") | $(seconds_since "$start") | |"
  cpu=$(postmaster_cpu); rows=$(rows_written); start=$(date +%s.%N)
  "$memloop" run "$folder" --db "$uri" --robot r1 --out "$work/server.csv" --set "${sets[@]}" >/dev/null
  wall=$(seconds_since "$start")
  sleep 1  # a backend's CPU reaches the postmaster's account as it exits
  rate=$(echo "($(rows_written) - $rows) / ($(postmaster_cpu) - $cpu)" | bc)
  echo "| $name | server | 1 | $(summary "$work/server.csv") | $wall | $rate |"
  clear_robots
  start=$(date +%s.%N)
  # The same images thrice: the robots do not import each other's places (all would match).
  for robot in r1 r2 r3; do
    "$memloop" run "$folder" --db "$uri" --robot $robot --out "$work/$robot.csv" \
      --set "${sets[@]}" memory.fleet_imports=0 >/dev/null &
  done
  wait
  echo "| $name | server (r1 of 3) | 3 | $(summary "$work/r1.csv") | $(seconds_since "$start") | |"
  start=$(date +%s.%N)
  for n in 2 3 4; do
    "$memloop" run "$folder" --db "$work/$n.db" --out "$work/$n.csv" --set "${sets[@]}" >/dev/null &
  done
  wait
  echo "| $name | file (1 of 3) | 3 | $(summary "$work/2.csv") | $(seconds_since "$start") | |"
done
