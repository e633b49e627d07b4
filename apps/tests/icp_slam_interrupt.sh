#!/bin/sh
# Ctrl-C stops rove icp-slam between two log entries: exit 130, a message
# saying how far it got and that nothing was written, no file (and no
# temporary file) in the output folder. Runs on the Radish Intel log (over a
# minute of mapping); skipped (exit 77) when the datasets are absent.
# Usage: icp_slam_interrupt.sh ROVE SOURCE_DIR WORKDIR DATASETS_DIR
set -u
rove=$1
source_dir=$2
work=$3
log="$4/radish/intel.clf.bz2"
if [ ! -f "$log" ]; then
  echo "skipped: $log is absent"
  exit 77
fi
rm -rf "$work"
mkdir -p "$work"
"$rove" icp-slam --no-progress "$source_dir/data/icp-slam_carmen.ini" "$log" -o "$work/out" \
  >"$work/stdout" 2>"$work/stderr" &
pid=$!
sleep 2
kill -INT "$pid"
wait "$pid"
status=$?
failures=0
if [ "$status" -ne 130 ]; then
  echo "FAIL: exit $status, expected 130"; cat "$work/stderr"; failures=$((failures + 1))
fi
if ! grep -q "interrupted after [0-9]* steps; nothing written" "$work/stderr"; then
  echo "FAIL: no message saying what was written:"; cat "$work/stderr"; failures=$((failures + 1))
fi
if [ -e "$work/out" ] && [ -n "$(ls -A "$work/out")" ]; then
  echo "FAIL: files were written:"; ls -A "$work/out"; failures=$((failures + 1))
fi
[ "$failures" -eq 0 ] && echo "icp-slam stopped cleanly on Ctrl-C"
exit "$failures"
