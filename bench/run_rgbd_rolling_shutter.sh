#!/usr/bin/env bash
# Calibrates the rolling shutter's readout time of TUM fr1's RGB camera
# without the ground truth: rove rgbd-slam on fr1/rpy (the shared datasets'
# first 205 frames) with readouts of 0 to 30 ms and three seeds each; the
# readout whose pose graph is the most self-consistent (the smallest final
# χ² per edge, the edges being PnP both ways, GICP and loop closures)
# is the camera's. The ATE against the ground truth is printed beside it,
# not used to choose.
# Usage: bench/run_rgbd_rolling_shutter.sh [ROVE_BINARY] [DATASETS_DIR]
set -euo pipefail
rove=${1:-build/release/apps/rove}
datasets=${2:-../shared/datasets}
seq=$datasets/rgbd/tum_fr1_rpy
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
printf '| readout (ms) | χ² per edge (mean of 3 seeds) | ATE RMSE (m, mean) | ATE RMSE per seed (m) |\n|---|---|---|---|\n'
for ms in 0 5 10 15 20 25 30; do
  for seed in 1 2 3; do
    printf '[rgbd-slam]\nrolling_shutter_readout = %s\nseed = %s\noctree_resolution = 0\n' "$(python3 -c "print($ms/1000)")" "$seed" \
      > "$out/c.ini"
    "$rove" rgbd-slam --no-progress --config "$out/c.ini" "$seq" -o "$out/r_${ms}_$seed" >/dev/null 2>&1 || true
  done
  python3 - "$out" "$ms" <<'PY'
import json, sys
out, ms = sys.argv[1], sys.argv[2]
runs = [json.load(open(f"{out}/r_{ms}_{s}/summary.json")) for s in (1, 2, 3)]
chi = [r["last_optimization"]["chi2_per_edge"] for r in runs]
ate = [r["ate"]["rmse_m"] for r in runs]
print(f"| {ms} | {sum(chi) / 3:.1f} | {sum(ate) / 3:.4f} | {' '.join(f'{a:.4f}' for a in ate)} |")
PY
done
