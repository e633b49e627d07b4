#!/usr/bin/env bash
# The Telecom loop check of `rove rbpf-slam`: MRPT's
# gridmapping_optimal_sampling.ini (25 particles, 0.07 m) on the bundled
# Telecom loop with seeds 1..N, each map compared (--reference) with the
# grid of `rove icp-slam`'s map of the same loop (its keyframes inserted
# into the same 0.07 m grid by `rove map build`): the share of cells known
# in both that agree, and the share of the RBPF map's occupied cells with a
# reference wall within one cell (a doubled wall fails it): of all of them,
# and of those the reference saw (known there; the reference holds only the
# 54 keyframes' scans, so far returns of the other scans are unknown to it).
# Usage: [ROVE_BIN=path/to/rove] bench/run_rbpf_slam_telecom_seeds.sh [seeds]
set -euo pipefail
cd "$(dirname "$0")/.."
seeds=${1:-10}
ini=data/mrpt/gridmapping_optimal_sampling.ini
rawlog=data/mrpt/2006-01ENE-21-SENA_Telecom_Faculty_one_loop_only.rawlog
work=build/bench/rbpf_slam_seeds
mkdir -p "$work"
. bench/rove_release.sh

"$rove" icp-slam --no-progress data/mrpt/icp-slam_demo_classic.ini "$rawlog" -o "$work/icp" > /dev/null
"$rove" map build "$ini" "$work/icp/map.simplemap" --section MappingApplication -o "$work/icp_grid" > /dev/null
reference="$work/icp_grid/map_00_occupancyGrid.yaml"

echo "| seed | cells compared | agreement | walls within one cell: all / where the reference saw | ESS/N mean | resamplings | issues | mapping s |"
echo "|---|---|---|---|---|---|---|---|"
for s in $(seq "$seeds"); do
  out="$work/seed_$s"
  set +e
  "$rove" rbpf-slam --no-progress --json --seed "$s" "$ini" "$rawlog" --reference "$reference" -o "$out" > "$out.json"
  status=$?
  set -e
  python3 - "$out.json" "$s" "$status" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
r = d["reference"]
issues = ",".join(i["code"] for i in d["issues"]) or "none"
print(f"| {sys.argv[2]} | {r['compared_cells']} | {100 * r['agreement']:.2f} % | {100 * r['wall_agreement']:.2f} % / "
      f"{100 * r['known_wall_agreement']:.2f} % "
      f"| {d['ess_mean']:.3f} | {d['resamplings']} | {issues} (exit {sys.argv[3]}) | {d['mapping_seconds']:.2f} |")
PY
done
