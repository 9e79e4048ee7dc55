#!/usr/bin/env bash
# The ROS node live on a camera's stream: a roscore on a free port, memloop_node in live mode
# (the newest image), and bench/ros_publish.py publishing a folder's images at RATE Hz; prints
# images processed and dropped, iteration time and the latency to each loop closure message.
# Usage: bench/ros_live.sh [IMAGES_DIR] (default ../shared/datasets/gp_walk_a/images)
# Environment: RATE=30, QUEUE=false, BUILD_DIR=build, SETS="name=value ..." (node parameters).
set -euo pipefail
cd "$(dirname "$0")/.."
build=${BUILD_DIR:-build}
images=${1:-../shared/datasets/gp_walk_a/images}
if [ ! -d "$images" ]; then
  echo "ros_live.sh: $images is absent: nothing to run" >&2
  exit 0
fi
work=$(mktemp -d)
port=$(/usr/bin/python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1",0)); print(s.getsockname()[1])')
export ROS_MASTER_URI=http://127.0.0.1:$port ROS_HOME=$work ROS_LOG_DIR=$work/log
export PYTHONPATH=$PWD/$build/ros/generated/python${PYTHONPATH:+:$PYTHONPATH}
roscore -p "$port" >"$work/roscore.log" 2>&1 &
core=$!
trap 'kill -INT $node $core 2>/dev/null; wait; rm -rf "$work"' EXIT
until rostopic list >/dev/null 2>&1; do sleep 0.2; done
params=()
for set in ${SETS:-}; do key=${set%%=*}; params+=("_${key//./\/}:=${set#*=}"); done
"$build/ros/memloop_node" image:=/camera/image_raw "_database:=$work/map.db" \
  "_queue:=${QUEUE:-false}" "${params[@]}" >"$work/node.log" 2>&1 &
node=$!
echo "machine: $(lscpu | sed -n 's/^Model name: *//p'), $(nproc) cores; $(date -u +%Y-%m-%d); memloop $(git rev-parse --short HEAD 2>/dev/null || echo '?'); $images"
/usr/bin/python3 bench/ros_publish.py "$images" "${RATE:-30}"
kill -INT $node
wait $node
tail -1 "$work/node.log"
