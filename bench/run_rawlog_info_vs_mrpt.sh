#!/usr/bin/env bash
# `rove rawlog info` against MRPT's `rawlog-edit --info` on the Radish Intel
# log (13,631 scans + 13,631 odometry readings) converted to an MRPT rawlog by
# MRPT's own carmen2rawlog: wall time and peak memory of each whole process,
# three runs each, alternating. Needs mrpt-apps (scripts/install-deps --peers)
# and ../shared/datasets/radish/intel.clf.bz2.
set -euo pipefail
cd "$(dirname "$0")/.."
data=../shared/datasets/radish/intel.clf.bz2
[ -f "$data" ] || { echo "missing $data" >&2; exit 1; }
work=build/bench/rawlog_info
mkdir -p "$work"
if [ ! -f "$work/intel.rawlog" ]; then
  bzcat "$data" > "$work/intel.clf"
  carmen2rawlog -i "$work/intel.clf" -o "$work/intel.rawlog" >/dev/null 2>&1
fi
cmake --preset release -DROVE_BUILD_TESTS=OFF >/dev/null
cmake --build --preset release --target rove >/dev/null
rove=build/release/apps/rove

echo "input: $work/intel.rawlog ($(stat -c %s "$work/intel.rawlog") bytes, gzip)"
for i in 1 2 3; do
  /usr/bin/time -f "rove        %e s  %M KB" "$rove" rawlog info --no-progress "$work/intel.rawlog" >/dev/null
  /usr/bin/time -f "rawlog-edit %e s  %M KB" rawlog-edit --info -i "$work/intel.rawlog" >/dev/null 2>"$work/mrpt.err" || true
  tail -n 1 "$work/mrpt.err"
done
