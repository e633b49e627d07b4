#!/usr/bin/env bash
# Closed-loop navigation benchmark (docs/navigation.md, "Benchmark"): 100
# random reachable start/goal pairs on each of two maps, driven in rove's
# simulator by each local planner, on one core.
#  - MRPT's Malaga campus map (2006-MalagaCampus.gridmap.gz, 8 cm cells);
#  - the grid of the Telecom Faculty loop: rove icp-slam on the bundled
#    rawlog (MRPT's icp-slam_demo_classic.ini), then rove map build with the
#    occupancy grid of MRPT's localization_demo.ini (6 cm cells).
# Usage: bench/run_nav_closed_loop.sh [pairs] [planners...]   (default: 100 teb reactive;
# also reactive-nd, reactive-vff)
set -euo pipefail
cd "$(dirname "$0")/.."
pairs=${1:-100}
shift || true
planners=${*:-teb reactive}
datasets=${ROVE_DATASETS_DIR:-$(pwd)/../shared/datasets}
work=build/bench/nav
mkdir -p "$work"
cmake --preset bench -DROVE_DATASETS_DIR="$datasets" >/dev/null
cmake --build --preset bench -j2 --target rove bench_nav_closed_loop >/dev/null
rove=build/bench/apps/rove
if [ ! -f "$work/telecom/map_00_occupancyGrid.yaml" ]; then
  "$rove" icp-slam --no-progress -o "$work/telecom_slam" >/dev/null
  "$rove" map build --section MetricMap /usr/share/mrpt/config_files/pf-localization/localization_demo.ini \
    "$work/telecom_slam/map.simplemap" -o "$work/telecom" >/dev/null
fi
for planner in $planners; do
  for map in "$datasets/mrpt/2006-MalagaCampus.gridmap.gz" "$work/telecom/map_00_occupancyGrid.yaml"; do
    name=$(basename "$map" | cut -d. -f1)
    build/bench/bench/bench_nav_closed_loop "$map" --pairs "$pairs" --planner "$planner" \
      --runs-out "$work/runs_${planner}_${name}.txt"
  done
done
