#!/usr/bin/env bash
# The Dask scale-out of `rove batch`: icp-slam over the Telecom rawlog and the
# Radish ACES log with four ICP pairing thresholds (8 runs), each ACES run
# scored against the log's Freiburg relations (`rove eval relations`), made
# one run after another (--serial, no Dask), on a local Dask cluster of one
# worker, and of two, in turn. Prints the wall times and the sweep's table
# (run times of the last serial round); the three tables must hold the same
# figures (checked here). Exit status 3 of a batch is expected: icp-slam
# accepts few ICP results on Telecom with the 0.2 m threshold.
# Usage: [ROVE_BIN=path/to/rove] [ROVE_DATASETS_DIR=...] bench/run_batch_sweep.sh [rounds]
# (ROVE_BIN's build must hold the Python bindings: target rove_python.)
set -euo pipefail
cd "$(dirname "$0")/.."
datasets=${ROVE_DATASETS_DIR:-../shared/datasets}
rounds=${1:-1}
work=build/bench/batch_sweep
rm -rf "$work"
mkdir -p "$work"
. bench/rove_release.sh
if [ -z "${ROVE_BIN:-}" ]; then
  cmake -S . -B build/bench-release -DROVE_PYTHON=ON >/dev/null
  cmake --build build/bench-release --target rove_python -j2 >/dev/null
fi

sweep=("icp-slam {config} {input} -o {out} --no-progress --max-range 50"
       --config data/icp-slam_carmen.ini
       --inputs data/mrpt/2006-01ENE-21-SENA_Telecom_Faculty_one_loop_only.rawlog "$datasets/radish/aces.clf.bz2"
       --param ICP.thresholdDist=0.2,0.3,0.4,0.6 --eval relations)
# Rounds interleave the three ways, so that the machine's load (shared
# machines) weighs on each alike.
for round in $(seq "$rounds"); do
  for mode in serial workers2 workers1; do
    case $mode in
      serial) opts=(--serial) ;;
      workers1) opts=(--workers 1) ;;
      workers2) opts=(--workers 2) ;;
    esac
    load=$(cut -d' ' -f1 /proc/loadavg)
    start=$(date +%s.%N)
    set +e
    "$rove" batch "${sweep[@]}" "${opts[@]}" -o "$work/$mode" > "$work/$mode.log"
    status=$?
    set -e
    end=$(date +%s.%N)
    printf "round %s, %-8s: exit %s, %.1f s from start to exit (load average before: %s)\n" \
      "$round" "$mode" "$status" "$(echo "$end - $start" | bc)" "$load"
  done
done

python3 - "$work" <<'PY'
import json, sys
work = sys.argv[1]
docs = {m: json.load(open(f"{work}/{m}/runs.json")) for m in ("serial", "workers1", "workers2")}
def figures(row):
    f = {k: v for k, v in row["figures"].items() if "seconds" not in k}
    return f, row["eval"]
for m in ("workers1", "workers2"):
    for a, b in zip(docs["serial"]["rows"], docs[m]["rows"]):
        assert figures(a) == figures(b), (m, a["name"])
print("same figures in the three tables")
print("| input | ICP.thresholdDist | status | ICP accepted | keyframes | relations used | translation error m (mean ± std) | rotation error ° (mean) | run s (serial) |")
print("|---|---|---|---|---|---|---|---|---|")
import math
for r in docs["serial"]["rows"]:
    e = r["eval"].get("relations", {})
    name = r["input"].rsplit("/", 1)[-1].split(".")[0][:20]
    if "used" in e:
        rel = (f"{e['used']} of {e['relations']} | {e['translation_m.mean']:.4f} ± {e['translation_m.std']:.4f} "
               f"| {math.degrees(e['rotation_rad.mean']):.3f}")
    else:
        rel = "– | – | –"
    print(f"| {name} | {r['params']['ICP.thresholdDist']} | {r['status']} | {r['figures']['icp_accepted']} of "
          f"{r['figures']['icp_runs']} | {r['figures']['keyframes']} | {rel} | {r['wall_seconds']:.1f} |")
for m, d in docs.items():
    cpu = sum(r.get("cpu_seconds") or 0 for r in d["rows"])
    longest = max(r["wall_seconds"] for r in d["rows"])
    print(f"{m}: batch wall {d['wall_seconds']:.1f} s (last round), runs' CPU {cpu:.1f} s, longest run {longest:.1f} s; "
          f"{d['ok']} ok, {d['with_issues']} with issues, {d['failed']} failed")
PY
