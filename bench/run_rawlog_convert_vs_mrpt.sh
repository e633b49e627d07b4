#!/usr/bin/env bash
# `rove rawlog convert` / `export-scans` / `export-odometry` against MRPT
# 2.5.8's tools on the Radish Intel log (13,631 scans, 26,915 ODOM lines),
# whole processes side by side in one run: wall time and peak RSS
# (/usr/bin/time), three runs each, alternating. The MRPT rawlog is made by
# MRPT's carmen2rawlog in a temporary directory. Needs mrpt-apps
# (scripts/install-deps --peers) and ../shared/datasets/radish/intel.clf.bz2.
#
#   bench/run_rawlog_convert_vs_mrpt.sh            # builds rove (Release) in build/bench-rawlog
#   ROVE=path/to/rove bench/run_rawlog_convert_vs_mrpt.sh
#
# Pairs (same input, same output kind):
#   CARMEN → rawlog:  rove convert --layout 2 intel.clf      vs  carmen2rawlog -i intel.clf
#   MRPT rawlog → rawlog (read all, write all, gzip):
#                     rove convert intel.rawlog              vs  rawlog-edit --cut --from-index 0
#   scans to text:    rove export-scans (+ export-odometry)  vs  rawlog-edit --export-2d-scans-txt
#                     (rawlog-edit writes the scan and the odometry file in one run; the
#                     script checks that both of rove's files equal rawlog-edit's byte for byte)
set -euo pipefail
cd "$(dirname "$0")/.."
data=../shared/datasets/radish/intel.clf.bz2
[ -f "$data" ] || { echo "missing $data" >&2; exit 1; }
if [ -z "${ROVE:-}" ]; then
  cmake -S . -B build/bench-rawlog -G Ninja -DCMAKE_BUILD_TYPE=Release -DROVE_BUILD_TESTS=OFF \
    -DROVE_BUILD_APPS=ON >/dev/null
  cmake --build build/bench-rawlog --target rove >/dev/null
  ROVE=build/bench-rawlog/apps/rove
fi
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
bzcat "$data" > "$work/intel.clf"
carmen2rawlog -q -i "$work/intel.clf" -o "$work/intel.rawlog" >/dev/null 2>&1

run() {  # run NAME CMD...: prints "NAME  seconds  peak-KB"
  local name=$1; shift
  /usr/bin/time -f "%e %M" -o "$work/time" "$@" >/dev/null 2>"$work/err" || {
    echo "$name failed:"; cat "$work/err"; exit 1; }
  read -r s kb < "$work/time"
  printf "%-34s %7.2f s %9d KB\n" "$name" "$s" "$kb"
}

echo "machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs)"
echo "input: intel.clf $(stat -c %s "$work/intel.clf") bytes; intel.rawlog (carmen2rawlog, gzip) $(stat -c %s "$work/intel.rawlog") bytes"
for i in 1 2 3; do
  echo "--- run $i"
  run "rove convert CARMEN --layout 2" "$ROVE" rawlog convert --no-progress --layout 2 "$work/intel.clf" "$work/r1.rawlog"
  run "carmen2rawlog" carmen2rawlog -q -w -i "$work/intel.clf" -o "$work/m1.rawlog"
  run "rove convert MRPT rawlog" "$ROVE" rawlog convert --no-progress "$work/intel.rawlog" "$work/r2.rawlog"
  run "rawlog-edit --cut --from-index 0" rawlog-edit -q -w --cut --from-index 0 -i "$work/intel.rawlog" -o "$work/m2.rawlog"
  run "rove export-scans" "$ROVE" rawlog export-scans --no-progress "$work/intel.rawlog" "$work/rove_FLASER.txt"
  run "rove export-odometry" "$ROVE" rawlog export-odometry --no-progress "$work/intel.rawlog" "$work/rove_ODOMETRY.txt"
  # rawlog-edit 2.5.8 joins the input's folder and the export name without a
# slash (/tmp/x/intel.rawlog -> /tmp/xintel_FLASER.txt): run it from the
# work directory on a relative path.
  run "rawlog-edit --export-2d-scans-txt" bash -c 'cd "$1" && rawlog-edit -q --export-2d-scans-txt -i intel.rawlog' _ "$work"
done
cmp "$work/rove_FLASER.txt" "$work/intel_FLASER.txt"
echo "scan export: identical to rawlog-edit's ($(wc -l < "$work/intel_FLASER.txt") lines)"
cmp "$work/rove_ODOMETRY.txt" "$work/intel_ODOMETRY.txt"
echo "odometry export: identical to rawlog-edit's ($(wc -l < "$work/intel_ODOMETRY.txt") lines)"
echo "sizes: rove CARMEN→rawlog $(stat -c %s "$work/r1.rawlog") B, carmen2rawlog $(stat -c %s "$work/m1.rawlog") B; rove MRPT→rove $(stat -c %s "$work/r2.rawlog") B, rawlog-edit cut $(stat -c %s "$work/m2.rawlog") B"
