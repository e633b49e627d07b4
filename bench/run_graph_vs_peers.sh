#!/usr/bin/env bash
# `rove graph-slam` against the Ceres 2.1 reference optimizer
# (tools/ceres_graph_reference: same χ², same initial guess, LM on
# SuiteSparse) and MRPT 2.5.8's `graph-slam --levmarq`, whole process, on the
# pose-graph datasets in ../shared/datasets/posegraph. Prints wall time, peak
# RSS and final χ² per tool, and the speed ratios. Each tool runs RUNS times
# (default 3), interleaved; the median time is reported.
#
#   bench/run_graph_vs_peers.sh [BUILD_DIR]   (default build/bench-graph)
#
# Needs libceres-dev and mrpt-apps (scripts/install-deps --peers).
set -euo pipefail
cd "$(dirname "$0")/.."
data=../shared/datasets/posegraph
[ -d "$data" ] || { echo "missing $data (the pose-graph datasets)" >&2; exit 1; }
build=${1:-build/bench-graph}
runs=${RUNS:-3}
if [ ! -x "$build/apps/rove/rove" ] || [ ! -x "$build/tools/ceres_graph_reference/ceres_graph_reference" ]; then
  cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DROVE_BUILD_TESTS=OFF \
    -DROVE_BUILD_APPS=ON -DROVE_BUILD_PEER_TOOLS=ON >/dev/null
  cmake --build "$build" --target rove ceres_graph_reference -j2 >/dev/null
fi
rove=$build/apps/rove/rove
ceres=$build/tools/ceres_graph_reference/ceres_graph_reference
command -v graph-slam >/dev/null || { echo "MRPT's graph-slam (mrpt-apps) is missing" >&2; exit 1; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# name file dimension initial-guess
sets="circle50 graph_2d_circle_50nodes.graph 2d as-is
w100 w100.graph 2d as-is
intel intel.g2o 2d as-is
intel_carlone intel_carlone.g2o 2d chordal
M3500 M3500.g2o 2d as-is
sphere2500 sphere2500.txt 3d as-is
torus3D torus3D.g2o 3d spanning-tree"

median() { sort -g | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}'; }
timed() {  # timed OUTFILE cmd... → prints "seconds KB" of the whole process
  local out=$1; shift
  /usr/bin/time -f "%e %M" -o "$work/time" "$@" >"$out" 2>&1 || true
  cat "$work/time"
}

echo "machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ *//'), load $(cut -d' ' -f1 /proc/loadavg)"
printf '%-14s %-8s | %-22s %-8s %-9s | %-22s %-8s %-9s | %-8s %-9s | %-7s %-7s\n' \
  dataset init "rove chi2" "rove s" "rove MB" "ceres chi2" "ceres s" "ceres MB" "mrpt s" "mrpt MB" "ceres/r" "mrpt/r"
echo "$sets" | while read -r name file dim init; do
  in=$data/$file
  : >"$work/t_rove"; : >"$work/t_ceres"; : >"$work/t_mrpt"
  for ((k = 0; k < runs; k++)); do
    timed "$work/rove.out" "$rove" graph-slam -i "$in" --$dim --init "$init" --json -o "$work/out.g2o" >>"$work/t_rove"
    timed "$work/ceres.out" "$ceres" -i "$in" --init "$init" -o "$work/ceres_out.g2o" >>"$work/t_ceres"
    timed "$work/mrpt.out" graph-slam --levmarq --$dim -i "$in" -o "$work/mrpt_out.graph" >>"$work/t_mrpt"
  done
  rchi=$(grep -o '"final_chi2": [^,]*' "$work/rove.out" | cut -d' ' -f2)
  cchi=$(grep -o 'chi2_final [^ ]*' "$work/ceres.out" | cut -d' ' -f2)
  rs=$(cut -d' ' -f1 "$work/t_rove" | median); rm=$(cut -d' ' -f2 "$work/t_rove" | median)
  cs=$(cut -d' ' -f1 "$work/t_ceres" | median); cm=$(cut -d' ' -f2 "$work/t_ceres" | median)
  ms=$(cut -d' ' -f1 "$work/t_mrpt" | median); mm=$(cut -d' ' -f2 "$work/t_mrpt" | median)
  printf '%-14s %-8s | %-22s %-8s %-9s | %-22s %-8s %-9s | %-8s %-9s | %-7s %-7s\n' \
    "$name" "$init" "$rchi" "$rs" "$(awk "BEGIN{printf \"%.1f\", $rm/1024}")" \
    "$cchi" "$cs" "$(awk "BEGIN{printf \"%.1f\", $cm/1024}")" \
    "$ms" "$(awk "BEGIN{printf \"%.1f\", $mm/1024}")" \
    "$(awk "BEGIN{printf \"%.1fx\", $cs/($rs>0?$rs:0.01)}")" \
    "$(awk "BEGIN{printf \"%.1fx\", $ms/($rs>0?$rs:0.01)}")"
  awk -v a="$rchi" -v b="$cchi" -v n="$name" 'BEGIN { d = (a - b) / b; if (d < 0) d = -d;
    if (d > 1e-6) printf "  WARNING %s: rove and Ceres chi2 differ by %.2g (relative)\n", n, d }'
done
