#!/usr/bin/env bash
# Times rove against MRPT 2.5.8 on 3D pose operations (bench/poses_vs_mrpt.cpp)
# and prints a table of ns/op and the speed-up of rove over MRPT.
#
#   bench/run_poses_vs_mrpt.sh [extra Google Benchmark flags]
#
# Configures the `bench` preset (Release, needs MRPT and Google Benchmark),
# builds only bench_poses_vs_mrpt, runs it with 5 repetitions and reports the
# medians. The raw JSON is left in build/bench/bench_poses_vs_mrpt.json.
set -euo pipefail

cd "$(dirname "$0")/.."
jobs="${ROVE_BENCH_JOBS:-2}"

cmake --preset bench >/dev/null
cmake --build build/bench --target bench_poses_vs_mrpt -j "$jobs"

json=build/bench/bench_poses_vs_mrpt.json
build/bench/bench/bench_poses_vs_mrpt \
  --benchmark_repetitions=5 --benchmark_report_aggregates_only=true \
  --benchmark_out="$json" --benchmark_out_format=json "$@" >/dev/null

cpu="$(lscpu | sed -n 's/^Model name:[[:space:]]*//p' | head -n1)"
echo "CPU: ${cpu} ($(nproc) cores available)"

python3 - "$json" <<'PY'
import json
import sys

with open(sys.argv[1]) as f:
    data = json.load(f)

median, stddev = {}, {}
for b in data["benchmarks"]:
    if b.get("run_type") != "aggregate":
        continue
    name = b["run_name"]
    scale = {"ns": 1.0, "us": 1e3, "ms": 1e6, "s": 1e9}[b.get("time_unit", "ns")]
    if b["aggregate_name"] == "median":
        median[name] = b["cpu_time"] * scale
    elif b["aggregate_name"] == "stddev":
        stddev[name] = b["cpu_time"] * scale

ops = []
for name in median:
    op = name.rsplit("/", 1)[0]
    if op not in ops:
        ops.append(op)

print(f"{'operation':<24}{'rove ns/op':>14}{'MRPT ns/op':>14}{'MRPT/rove':>11}")
for op in ops:
    r, m = median.get(op + "/rove"), median.get(op + "/mrpt")
    if r is None or m is None:
        continue
    rs = f"{r:.2f}±{stddev.get(op + '/rove', 0.0):.2f}"
    ms = f"{m:.2f}±{stddev.get(op + '/mrpt', 0.0):.2f}"
    print(f"{op:<24}{rs:>14}{ms:>14}{m / r:>10.2f}x")
print("(CPU time, median ± standard deviation of 5 repetitions)")
PY
