#!/bin/sh
# `rove graph-slam` on careless and hostile input: every case must end with
# the exit status and the message stated, and never harm its input.
#   graph_safety.sh ROVE DATASETS_POSEGRAPH WORK_DIR
set -u
rove=$1 data=$2 work=$3
rm -rf "$work" && mkdir -p "$work" || exit 1
failures=0
# expect STATUS REGEX -- ARGS...: runs rove ARGS, checks the exit status and
# that the combined output matches REGEX (grep -E).
expect() {
  want=$1 pattern=$2
  shift 3
  out=$("$rove" "$@" 2>&1)
  got=$?
  if [ "$got" -ne "$want" ] || ! printf '%s' "$out" | grep -Eq -- "$pattern"; then
    echo "FAIL: rove $* -> exit $got (expected $want), output:"
    printf '%s\n' "$out" | head -20
    failures=$((failures + 1))
  fi
}
cp "$data/intel.g2o" "$work/in.g2o"
cp "$data/graph_2d_circle_50nodes.graph" "$work/circle.graph"

# A level that does not exist: an error naming the flag and the levels.
expect 1 "--level 99.*levels present: 0 \(2512 edges\)" -- graph-slam -i "$work/in.g2o" --level 99
# Outputs over the input are refused, and the input stays as it was.
expect 1 "refusing to write over the input" -- graph-slam -i "$work/circle.graph" --plot "$work/circle.graph"
expect 1 "refusing to write over the input" -- graph-slam -i "$work/in.g2o" -o "$work/./in.g2o"
expect 1 "refusing to write over the input" -- graph-slam -i "$work/in.g2o" --ground-truth "$work/circle.graph" -o "$work/circle.graph"
cmp -s "$work/in.g2o" "$data/intel.g2o" || { echo "FAIL: the input was modified"; failures=$((failures + 1)); }
cmp -s "$work/circle.graph" "$data/graph_2d_circle_50nodes.graph" || { echo "FAIL: the circle input was modified"; failures=$((failures + 1)); }
# An output folder that does not exist is found before the optimization.
expect 1 "missing-folder.*does not exist" -- graph-slam -i "$work/in.g2o" -o "$work/missing-folder/out.g2o"
# Devices and directories are refused, not read.
expect 1 "/dev/zero.*not a regular file" -- graph-slam -i /dev/zero
expect 1 "/dev/urandom.*not a regular file" -- graph-slam -i /dev/urandom --2d
expect 1 "directory" -- graph-slam -i "$work"
# Thread counts go through one check that names the flag.
expect 1 "--threads.*1 to 256" -- graph-slam -i "$work/in.g2o" --threads 100000
expect 1 "--threads.*1 to 256" -- graph-slam -i "$work/in.g2o" --threads -3
# Stopping at the iteration limit is an issue: exit 3, named in the summary and the JSON.
expect 3 "warning: max-iterations" -- graph-slam -i "$work/in.g2o" --max-iters 2
expect 3 "\"code\": \"max-iterations\"" -- graph-slam -i "$work/in.g2o" --max-iters 2 --json
# The default start says which guess it used.
expect 0 "initial guess  chordal \(auto" -- graph-slam -i "$work/in.g2o"
expect 0 "\"init\": \"chordal\"" -- graph-slam -i "$work/in.g2o" --json
expect 0 "\"issues\": \[\]" -- graph-slam -i "$work/in.g2o" --json
# Edges only: the poses come from odometry, and the summary says so.
printf 'EDGE2 0 1 1 0 0 1 0 1 1 0 0\nEDGE2 1 2 1 0 0 1 0 1 1 0 0\n' > "$work/edges.graph"
expect 0 "built from odometry" -- graph-slam -i "$work/edges.graph"
expect 0 "\"vertices_from\": \"odometry\"" -- graph-slam -i "$work/edges.graph" --info --json
# Information matrices that are not positive definite: refused, with the count,
# the first edge's line and the option; repaired on request, and counted.
printf 'VERTEX2 0 0 0 0\nVERTEX2 1 1 0 0\nVERTEX2 2 2 0 0\nEDGE2 0 1 1 0 0 1 0 1 1 0 0\nEDGE2 1 2 1 0 0 1 0 -1 1 0 0\n' > "$work/npd.graph"
expect 1 "npd\.graph:5.*1 of 2 edges.*--repair-information nearest-psd" -- graph-slam -i "$work/npd.graph"
expect 0 "1 of 2 edges repaired" -- graph-slam -i "$work/npd.graph" --repair-information nearest-psd
expect 0 "\"repaired_information_edges\": 1" -- graph-slam -i "$work/npd.graph" --repair-information nearest-psd --json
# A non-UTF-8 file name keeps --json valid JSON.
odd=$(printf "$work/odd\\377.g2o")
cp "$work/in.g2o" "$odd"
if command -v python3 >/dev/null; then
  if ! "$rove" graph-slam -i "$odd" --json | python3 -c 'import json,sys; json.load(sys.stdin)'; then
    echo "FAIL: --json with a non-UTF-8 path is not valid JSON"
    failures=$((failures + 1))
  fi
fi
# A ground truth that shares too few vertices: the flag and the file are named.
printf 'VERTEX2 5000 0 0 0\nVERTEX2 5001 1 0 0\n' > "$work/far.graph"
expect 1 "--ground-truth .*far\.graph: only 0 of its vertex ids" -- graph-slam -i "$work/in.g2o" --ground-truth "$work/far.graph"
# Outputs are complete files (no temporary left beside them).
expect 0 "plot " -- graph-slam -i "$work/circle.graph" -o "$work/out.g2o" --plot "$work/out.png"
if ls -A "$work" | grep -q rove-tmp; then echo "FAIL: a temporary file was left"; failures=$((failures + 1)); fi
head -c 8 "$work/out.png" | od -An -c | grep -q "P   N   G" || { echo "FAIL: the plot is not a PNG"; failures=$((failures + 1)); }

# Ctrl-C (SIGINT; rove installs its handler even where the shell starts a
# background job with SIGINT ignored) stops
# the optimizer between iterations: exit 130, no output, no temporary file.
# torus3D from its stored poses takes over 15 s to reach its iteration limit.
"$rove" graph-slam -i "$data/torus3D.g2o" --init as-is -o "$work/stopped.g2o" >/dev/null 2>&1 &
pid=$!
sleep 1.5
kill -INT "$pid"
wait "$pid"
status=$?
if [ "$status" -ne 130 ] || [ -e "$work/stopped.g2o" ] || ls -A "$work" | grep -q rove-tmp; then
  echo "FAIL: an interrupted optimization ended with $status or left a file"
  failures=$((failures + 1))
fi

[ "$failures" -eq 0 ] && echo "graph-slam safety: all cases passed"
exit "$failures"
