#!/usr/bin/env bash
# rove rgbd-slam on TUM fr1/rpy (the shared datasets' first 205 frames), on
# one core (taskset), with rove's defaults and the RGB-D SLAM tutorial's
# preset: ATE, frames per second (wall and CPU), seconds per stage (the
# octree map, map.bt, and the GICP edges included).
# Usage: bench/run_rgbd_slam.sh [ROVE_BINARY] [DATASETS_DIR]
set -euo pipefail
rove=${1:-build/release/apps/rove}
datasets=${2:-../shared/datasets}
seq=$datasets/rgbd/tum_fr1_rpy
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
printf '| preset | ATE RMSE (m) | frames | lost | keyframes | loops | fps (processing, wall) | fps (with reading, wall) | CPU s (process) | features s | matching s | PnP s | loops s | graph s | map s | octree s | GICP edges s | reading s |\n'
printf '|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n'
for preset in default tutorial; do
  /usr/bin/time -f '%U %S' -o "$out/time_$preset" taskset -c 0 "$rove" rgbd-slam --no-progress --json \
    --preset "$preset" "$seq" -o "$out/$preset" >/dev/null || true
  python3 - "$out/$preset/summary.json" "$out/time_$preset" "$preset" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
u, k = map(float, open(sys.argv[2]).read().split()[-2:])
t = s["seconds"]
ate = s.get("ate", {}).get("rmse_m", float("nan"))
print(f"| {sys.argv[3]} | {ate:.4f} | {s['frames']} | {s['lost']} | {s['keyframes']} | "
      f"{s['loops_accepted']}/{s['loop_checks']} | {s['frames_per_second']:.1f} | "
      f"{s['frames_per_second_with_reading']:.1f} | {u + k:.2f} | {t['features']:.2f} | "
      f"{t['matching']:.2f} | {t['pnp']:.2f} | {t['loop_closure']:.2f} | {t['graph']:.2f} | "
      f"{t['map']:.2f} | {t.get('octree', float('nan')):.2f} | {t.get('icp', float('nan')):.2f} | "
      f"{t['reading']:.2f} |")
PY
done
