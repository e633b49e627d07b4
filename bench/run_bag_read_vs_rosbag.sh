#!/usr/bin/env bash
# Reading a ROS 1 bag: rove (`rove rawlog info`, every message parsed and
# converted to rove observations) against rosbag's own Python API
# (python3-rosbag: `Bag.read_messages()`, every message deserialized into
# its Python class) on the same bag: the Radish Intel log (13,631 scans +
# 13,631 odometry readings) written as a bag by `rove rawlog convert`, with
# uncompressed, lz4 and bz2 chunks. Wall time of each whole process, three
# runs each, alternating; for rosbag also the time after its import (which
# alone takes about a second: it loads gnupg and Cryptodome). Needs the rove::ros adapter and python3-rosbag
# (scripts/install-deps --ros) and ../shared/datasets/radish/intel.clf.bz2.
set -euo pipefail
cd "$(dirname "$0")/.."
data=../shared/datasets/radish/intel.clf.bz2
[ -f "$data" ] || { echo "missing $data" >&2; exit 1; }
work=build/bench/bag_read
mkdir -p "$work"
cmake --preset release -DROVE_BUILD_TESTS=OFF >/dev/null
cmake --build --preset release --target rove >/dev/null
rove=build/release/apps/rove
for c in none lz4 bz2; do
  [ -f "$work/intel_$c.bag" ] ||
    "$rove" rawlog convert --no-progress --compression "$c" "$data" "$work/intel_$c.bag" >/dev/null
done
cat > "$work/read_rosbag.py" <<'PY'
import sys
import time
import rosbag
t0 = time.perf_counter()
n = 0
with rosbag.Bag(sys.argv[1]) as bag:
    for _topic, _msg, _t in bag.read_messages():
        n += 1
print(n, "messages, %.2f s after import" % (time.perf_counter() - t0))
PY
for c in none lz4 bz2; do
  bag="$work/intel_$c.bag"
  echo "input: $bag ($(stat -c %s "$bag") bytes, $c chunks)"
  "$rove" rawlog info --no-progress "$bag" | grep -E "^entries|RangeScan2D"
  /usr/bin/python3 "$work/read_rosbag.py" "$bag"
  for i in 1 2 3; do
    /usr/bin/time -f "  rove rawlog info        %e s  %M KB" "$rove" rawlog info --no-progress "$bag" >/dev/null
    /usr/bin/time -f "  rosbag read_messages()  %e s  %M KB" /usr/bin/python3 "$work/read_rosbag.py" "$bag"
  done
done
