#!/usr/bin/env bash
# How fast `memloop view` opens a map: seconds from its start until it serves, then the time of
# each request the first pages make (docs/viewer.md).
# Usage: bench/view_open.sh MAP IMAGES_DIR [PORT]   (BUILD_DIR: default build)
# The map of docs/viewer.md's figure:
#   memloop generate /tmp/big --places 5000
#   memloop run /tmp/big/images --db /tmp/big.db --set memory.time_limit_ms=0 \
#       memory.max_wm_locations=100 features.max_features=100
set -euo pipefail
map=$1
images=$2
port=${3:-8790}
memloop=${BUILD_DIR:-build}/memloop
out=$(mktemp)
start=$(date +%s.%N)
"$memloop" view "$map" --images "$images" --port "$port" > "$out" 2>&1 &
pid=$!
trap 'kill $pid 2> /dev/null; rm -f "$out"' EXIT
until grep -q "serves" "$out"; do
  kill -0 $pid 2> /dev/null || { cat "$out"; exit 1; }
  sleep 0.01
done
printf "serving after %.3f s\n" "$(echo "$(date +%s.%N) - $start" | bc)"
for path in / /api/summary "/api/loop_closures?offset=0&limit=50" \
            "/api/images?session=0&offset=0&limit=120" /api/locations/1 /api/thumbnails/0 \
            "/api/loop_closures?offset=0&limit=100000"; do
  curl -s -o /dev/null -w "%{time_total} s  %{size_download} bytes  $path\n" \
       "http://127.0.0.1:$port$path"
done
