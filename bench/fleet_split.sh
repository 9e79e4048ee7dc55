#!/usr/bin/env bash
# Robots that find each other's places, on a real data set split between robots (docs/fleet.md).
# DATASET's images (DATASET/images, with DATASET/ground_truth_pairs.csv) are cut into ROBOTS
# consecutive stretches, one robot each (r1 the first); the data set's loop pairs between two
# stretches are the fleet's ground truth. On a private server (bench/private_server.sh), T_time
# off (SETS adds parameters):
#   - one robot on all the images: its loop closures at the images whose loop is in an earlier
#     stretch (the cross pairs), the reference;
#   - the robots one after the other, each catching up with the fleet before its first image;
#   - the robots all at once, each finding what the others have stored so far: with a WM budget
#     of AT_ONCE_WM locations (60), so that places reach the server as they leave WM.
# Per robot: memloop fleet eval's precision and recall on the cross pairs, and the median
# iteration time.
# Usage: bench/fleet_split.sh [DATASET] [ROBOTS]   (default ../shared/datasets/lip6_outdoor 2)
set -euo pipefail
cd "$(dirname "$0")/.."
memloop=$PWD/${BUILD_DIR:-build}/memloop
dataset=${1:-../shared/datasets/lip6_outdoor}
robots=${2:-2}
read -r -a extra <<<"${SETS:-}"
sets=(memory.time_limit_ms=0 "${extra[@]}")
source bench/private_server.sh
names=()
for ((r = 1; r <= robots; ++r)); do names+=("r$r"); done
"$memloop" fleet init "postgresql://admin@/fleet?host=$work" "${names[@]/#/--robot=}" >/dev/null

# The stretches (links to the images) and the cross pairs, as memloop fleet eval reads them.
/usr/bin/python3 - "$dataset" "$robots" "$work" <<'PY'
import csv, os, re, sys
dataset, robots, work = sys.argv[1], int(sys.argv[2]), sys.argv[3]
# In the order memloop reads a folder: numbers within names by value (2.jpg before 10.jpg).
natural = lambda name: [int(t) if t.isdigit() else t for t in re.split(r"(\d+)", name)]
images = sorted(os.listdir(os.path.join(dataset, "images")), key=natural)
size = -(-len(images) // robots)
robot_of = {}
for r in range(robots):
    folder = os.path.join(work, f"r{r + 1}")
    os.makedirs(folder)
    for name in images[r * size:(r + 1) * size]:
        os.symlink(os.path.abspath(os.path.join(dataset, "images", name)), os.path.join(folder, name))
        robot_of[name] = f"r{r + 1}"
# The data set's ignored band (ground_truth_ignore.csv) likewise: fleet_ignore.csv.
for source, target in (("ground_truth_pairs.csv", "fleet_pairs.csv"),
                       ("ground_truth_ignore.csv", "fleet_ignore.csv")):
    if not os.path.exists(os.path.join(dataset, source)):
        continue
    with open(os.path.join(work, target), "w") as out:
        out.write("robot,image,other,other_image\n")
        for row in csv.DictReader(open(os.path.join(dataset, source))):
            q, m = row["query"], row["match"]
            if q in robot_of and m in robot_of and robot_of[q] != robot_of[m]:
                out.write(f"{robot_of[q]},{q},{robot_of[m]},{m}\n")
PY

# Of a whole run's CSV, at the images of a later stretch whose loop is in an earlier one (the
# cross images): loop closures, true ones (with an image of the cross pairs), and the recall.
whole_on_cross() {
  /usr/bin/python3 - "$1" "$work/fleet_pairs.csv" <<'PY'
import csv, sys
pairs = {}
for row in csv.DictReader(open(sys.argv[2])):
    if row["robot"] > row["other"]:
        pairs.setdefault(row["image"], set()).add(row["other_image"])
rows = list(csv.DictReader(open(sys.argv[1])))
name = {r["image"]: r["name"] for r in rows}
found = detections = 0
for r in rows:
    if r["name"] not in pairs or not r["matched_images"]:
        continue
    matched = {name[i] for i in r["matched_images"].split(";")}
    detections += 1
    found += bool(matched & pairs[r["name"]])
print(f"{detections} | {found} | {len(pairs)} | {100 * found / len(pairs):.1f}%")
PY
}
median_ms() {
  /usr/bin/python3 -c "import csv,statistics,sys; print(f'{statistics.median(float(r[\"iteration_ms\"]) for r in csv.DictReader(open(sys.argv[1]))):.1f}')" "$1"
}
clear_robots() {
  for table in $(psql -d fleet -c "SELECT tablename FROM pg_tables WHERE schemaname='memloop'"); do
    psql -d fleet -c "DELETE FROM memloop.$table"
  done
}
evaluate() {  # $1: the case's name
  runs=()
  for robot in "${names[@]}"; do runs+=("$robot=$work/$robot.csv"); done
  echo "$1:"
  "$memloop" fleet eval "$work/fleet_pairs.csv" "${runs[@]}"
  for robot in "${names[@]}"; do echo "  $robot median $(median_ms "$work/$robot.csv") ms"; done
  echo
}

echo "machine: $(lscpu | sed -n 's/^Model name: *//p'), $(nproc) cores; $(date -u +%Y-%m-%d); memloop $(git rev-parse --short HEAD 2>/dev/null || echo '?'); $(basename "$dataset") in $robots stretches; --set ${sets[*]}"
echo
"$memloop" run "$dataset/images" --db "$work/whole.db" --out "$work/whole.csv" --set "${sets[@]}" >/dev/null
echo "one robot, all the images: at the cross images, detections | true | cross images | recall"
echo "  $(whole_on_cross "$work/whole.csv"), median $(median_ms "$work/whole.csv") ms"
echo
for robot in "${names[@]}"; do
  "$memloop" run "$work/$robot" --db "$uri" --robot "$robot" --fleet-catch-up \
    --out "$work/$robot.csv" --set "${sets[@]}" >/dev/null
done
evaluate "one after the other, each catching up first"
clear_robots
for robot in "${names[@]}"; do
  "$memloop" run "$work/$robot" --db "$uri" --robot "$robot" --out "$work/$robot.csv" \
    --set "${sets[@]}" "memory.max_wm_locations=${AT_ONCE_WM:-60}" >/dev/null &
done
wait
evaluate "all at once, WM budget ${AT_ONCE_WM:-60}"
