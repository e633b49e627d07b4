#!/usr/bin/env bash
# `rove graph-slam` against the Ceres 2.1 reference optimizer
# (tools/ceres_graph_reference: same χ², same initial guess, same trust-region
# method, sparse normal Cholesky on SuiteSparse) and MRPT 2.5.8's
# `graph-slam --levmarq`, whole process, on the pose-graph datasets in
# ../shared/datasets/posegraph. Prints wall time, CPU time, peak RSS and final
# χ² per tool, and the speed ratios. Each tool runs RUNS times (default 3),
# interleaved; the median is reported. Wall time ("s") is the goal's measure;
# CPU time (user + system, "cpu") is printed beside it because on a shared,
# loaded machine wall time mostly measures the wait for a core.
#
#   [SOLVER=dogleg|lm] [RUNS=3] [SETS="intel M3500"] bench/run_graph_vs_peers.sh [BUILD_DIR]
#
# SOLVER (default dogleg, rove's default) is given to rove and to Ceres
# (Powell's dog-leg or Levenberg–Marquardt), so the two run the same method;
# MRPT always runs its --levmarq. BUILD_DIR defaults to build/bench-graph.
#
# Needs libceres-dev and mrpt-apps (scripts/install-deps --peers).
set -euo pipefail
cd "$(dirname "$0")/.."
data=../shared/datasets/posegraph
[ -d "$data" ] || { echo "missing $data (the pose-graph datasets)" >&2; exit 1; }
build=${1:-build/bench-graph}
runs=${RUNS:-3}
solver=${SOLVER:-dogleg}
if [ ! -x "$build/apps/rove" ] || [ ! -x "$build/tools/ceres_graph_reference/ceres_graph_reference" ]; then
  cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DROVE_BUILD_TESTS=OFF \
    -DROVE_BUILD_APPS=ON -DROVE_BUILD_PEER_TOOLS=ON >/dev/null
  cmake --build "$build" --target rove ceres_graph_reference -j2 >/dev/null
fi
rove=$build/apps/rove
ceres=$build/tools/ceres_graph_reference/ceres_graph_reference
command -v graph-slam >/dev/null || { echo "MRPT's graph-slam (mrpt-apps) is missing" >&2; exit 1; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# name file dimension initial-guess processes-per-measurement
sets="circle50 graph_2d_circle_50nodes.graph 2d as-is 20
w100 w100.graph 2d as-is 20
intel intel.g2o 2d as-is 5
intel_carlone intel_carlone.g2o 2d chordal 5
M3500 M3500.g2o 2d as-is 5
sphere2500 sphere2500.txt 3d as-is 1
torus3D torus3D.g2o 3d spanning-tree 1"

median() { sort -g | awk '{a[NR]=$1} END {if (NR) print a[int((NR+1)/2)]}'; }
# timed N OUTFILE cmd... → "wall_s KB cpu_s" of one whole process, or "fail".
# N > 1 runs the process N times in a row under one clock and divides, for
# the graphs that take a few milliseconds (below /usr/bin/time's 10 ms).
# (rove and Ceres only: MRPT takes over 0.2 s of CPU on every graph.)
timed() {
  local n=$1 out=$2; shift 2
  if /usr/bin/time -f "%e %M %U %S" -o "$work/time" bash -c \
      'n=$1 out=$2; shift 2; for ((i = 0; i < n; i++)); do "$@" >"$out" 2>&1 || exit 1; done' \
      _ "$n" "$out" "$@"; then
    awk -v n="$n" '{printf "%.4f %s %.4f\n", $1 / n, $2, ($3 + $4) / n}' "$work/time"
  else
    echo "fail fail fail"
  fi
}
col() { cut -d' ' -f"$1" "$2" | { grep -v fail || true; } | median; }
ratio() { awk -v a="$1" -v b="$2" 'BEGIN { if (a == "" || b == "" || b <= 0) print "-"; else printf "%.1fx", a / b }'; }
mb() { awk -v k="$1" 'BEGIN { if (k == "") print "-"; else printf "%.1f", k / 1024 }'; }

blas=$(readlink -f /usr/lib/x86_64-linux-gnu/libblas.so.3 2>/dev/null || echo unknown)
# `rove graph-slam` opts in to rove::configure_blas_for_this_cpu(), which sets
# OPENBLAS_CORETYPE from the CPU's instruction sets when the user has not
# (OpenBLAS 0.3.21 falls back to SSE3 kernels on CPUs newer than it knows;
# see rove/graph/blas_tuning.h; the library itself never sets it). Ceres gets
# the same setting here, so both factorize with the same kernels.
if [ -z "${OPENBLAS_CORETYPE:-}" ]; then
  flags=$(grep -m1 '^flags' /proc/cpuinfo)
  has() { case " $flags " in *" $1 "*) return 0 ;; *) return 1 ;; esac; }
  if has avx512f && has avx512bw && has avx512dq && has avx512vl; then
    export OPENBLAS_CORETYPE=SkylakeX
  elif has avx2 && has fma; then
    export OPENBLAS_CORETYPE=Haswell
  fi
fi
echo "machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ *//'), load $(cut -d' ' -f1 /proc/loadavg); BLAS $blas (OPENBLAS_CORETYPE=${OPENBLAS_CORETYPE:-auto}); rove and Ceres: $solver"
printf '%-13s %-13s| %-16s %-6s %-6s %-6s| %-16s %-6s %-6s %-6s| %-6s %-6s %-6s| %-13s %-13s\n' \
  dataset init "rove chi2" "s" "cpu" "MB" "ceres chi2" "s" "cpu" "MB" "mrpt s" "cpu" "MB" "ceres/rove" "mrpt/rove"
echo "                                                                                                    (wall, cpu)   (wall, cpu)"
echo "$sets" | while read -r name file dim init batch; do
  case " ${SETS:-$name} " in *" $name "*) ;; *) continue ;; esac
  in=$data/$file
  # MRPT has no chordal or odometry initial guess and cannot read a file
  # without vertex records (sphere2500.txt: map::at): it gets the same initial
  # guess as rove and Ceres, written by rove beforehand (not timed).
  mrpt_in=$in
  if [ "$init" != as-is ] || ! grep -qi '^VERTEX' "$in"; then
    mrpt_in=$work/${name}_init.graph
    # --max-iters 0 writes the initial guess; rove reports the iteration
    # limit as an issue (exit 3), which is expected here.
    "$rove" graph-slam -i "$in" --$dim --init "$init" --max-iters 0 -o "$mrpt_in" >/dev/null 2>&1 ||
      [ $? -eq 3 ] || { echo "rove could not write the initial guess of $name" >&2; exit 1; }
  fi
  : >"$work/t_rove"; : >"$work/t_ceres"; : >"$work/t_mrpt"
  for ((k = 0; k < runs; k++)); do
    timed "$batch" "$work/rove.out" "$rove" graph-slam -i "$in" --$dim --init "$init" --solver "$solver" --json -o "$work/out.g2o" >>"$work/t_rove"
    timed "$batch" "$work/ceres.out" "$ceres" -i "$in" --init "$init" --solver "$solver" -o "$work/ceres_out.g2o" >>"$work/t_ceres"
    timed 1 "$work/mrpt.out" graph-slam --levmarq --$dim -i "$mrpt_in" -o "$work/mrpt_out.graph" >>"$work/t_mrpt"
  done
  rchi=$(grep -o '"final_chi2": [^,]*' "$work/rove.out" | cut -d' ' -f2 || true)
  cchi=$(grep -o 'chi2_final [^ ]*' "$work/ceres.out" | cut -d' ' -f2 || true)
  rs=$(col 1 "$work/t_rove"); rm=$(col 2 "$work/t_rove"); rc=$(col 3 "$work/t_rove")
  cs=$(col 1 "$work/t_ceres"); cm=$(col 2 "$work/t_ceres"); cc=$(col 3 "$work/t_ceres")
  ms=$(col 1 "$work/t_mrpt"); mm=$(col 2 "$work/t_mrpt"); mc=$(col 3 "$work/t_mrpt")
  printf '%-13s %-13s| %-16.10g %-6s %-6s %-6s| %-16.10g %-6s %-6s %-6s| %-6s %-6s %-6s| %-13s %-13s\n' \
    "$name" "$init" "${rchi:-0}" "$rs" "$rc" "$(mb "$rm")" "${cchi:-0}" "$cs" "$cc" "$(mb "$cm")" \
    "${ms:-fail}" "${mc:-fail}" "$(mb "$mm")" \
    "$(ratio "$cs" "$rs"), $(ratio "$cc" "$rc")" "$(ratio "$ms" "$rs"), $(ratio "$mc" "$rc")"
  awk -v a="$rchi" -v b="$cchi" -v n="$name" 'BEGIN { d = (a - b) / b; if (d < 0) d = -d;
    if (d > 1e-6) printf "  WARNING %s: rove and Ceres chi2 differ by %.2g (relative)\n", n, d }'
done
echo "load at the end: $(cut -d' ' -f1-3 /proc/loadavg)"
