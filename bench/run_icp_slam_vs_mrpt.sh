#!/usr/bin/env bash
# `rove icp-slam` against MRPT 2.5.8's `icp-slam` on the bundled demo (Telecom
# Faculty loop, 224 steps, MRPT's icp-slam_demo_classic.ini and _LM.ini),
# side by side in one run: whole-process wall time and peak RSS
# (/usr/bin/time -v), the mapping loop alone (MRPT: sum of its per-step
# "Map building executed in" times; rove: mapping_seconds of its summary),
# and the agreement of the two paths (position RMSE, final-pose difference).
# MRPT runs headless: SHOW_PROGRESS_3D_REAL_TIME=0, SAVE_3D_SCENE=0.
# rove runs with --arithmetic mrpt (MRPT's run to the bit, the same work) unless
# ARITHMETIC=double is set (rove's default arithmetic; its path then differs
# from MRPT's by rounding).
# Needs mrpt-apps. Usage: [ARITHMETIC=double] bench/run_icp_slam_vs_mrpt.sh [runs]
set -euo pipefail
cd "$(dirname "$0")/.."
root=$(pwd)
runs=${1:-5}
arithmetic=${ARITHMETIC:-mrpt}
echo "rove icp-slam --arithmetic $arithmetic"
command -v icp-slam >/dev/null || { echo "icp-slam (mrpt-apps) is not installed" >&2; exit 1; }
rawlog="$root/data/mrpt/2006-01ENE-21-SENA_Telecom_Faculty_one_loop_only.rawlog"
work=build/bench/icp_slam
mkdir -p "$work"
cmake -S . -B build/bench-release -DCMAKE_BUILD_TYPE=Release -DROVE_BUILD_TESTS=OFF >/dev/null
cmake --build build/bench-release --target rove -j2 >/dev/null
rove=build/bench-release/apps/rove

median() { sort -g | awk '{a[NR]=$1} END {print (NR%2 ? a[(NR+1)/2] : (a[NR/2]+a[NR/2+1])/2)}'; }
field() { awk -v k="$2" '$0 ~ k {print $NF}' "$1"; }

for variant in classic LM; do
  sed -e "s|^rawlog_file *=.*|rawlog_file=$rawlog|" \
      -e 's|^SHOW_PROGRESS_3D_REAL_TIME *=.*|SHOW_PROGRESS_3D_REAL_TIME=0|' \
      -e 's|^SAVE_3D_SCENE *=.*|SAVE_3D_SCENE=0|' \
      -e "s|^logOutput_dir *=.*|logOutput_dir=$root/$work/mrpt_$variant|" \
      "data/mrpt/icp-slam_demo_$variant.ini" > "$work/mrpt_$variant.ini"
  : > "$work/$variant.times"
  for i in $(seq "$runs"); do
    /usr/bin/time -v icp-slam "$work/mrpt_$variant.ini" > "$work/mrpt_$variant.log" 2> "$work/mrpt_$variant.time"
    mrpt_loop=$(grep -o 'Map building executed in [0-9.]*ms' "$work/mrpt_$variant.log" | awk '{s += $5} END {printf "%.4f", s / 1000}')
    mrpt_wall=$(grep 'Elapsed (wall clock)' "$work/mrpt_$variant.time" | awk '{print $NF}' | awk -F: '{print $(NF-1)*60 + $NF}')
    mrpt_rss=$(field "$work/mrpt_$variant.time" 'Maximum resident')
    /usr/bin/time -v "$rove" icp-slam --json --no-progress --arithmetic "$arithmetic" "data/mrpt/icp-slam_demo_$variant.ini" "$rawlog" \
      -o "$work/rove_$variant" > "$work/rove_$variant.json" 2> "$work/rove_$variant.time"
    rove_loop=$(grep '"mapping_seconds"' "$work/rove_$variant.json" | tr -dc '0-9.')
    rove_wall=$(grep 'Elapsed (wall clock)' "$work/rove_$variant.time" | awk '{print $NF}' | awk -F: '{print $(NF-1)*60 + $NF}')
    rove_rss=$(field "$work/rove_$variant.time" 'Maximum resident')
    echo "$mrpt_loop $mrpt_wall $mrpt_rss $rove_loop $rove_wall $rove_rss" >> "$work/$variant.times"
  done
  col() { awk -v c="$1" '{print $c}' "$work/$variant.times" | median; }
  ml=$(col 1); mw=$(col 2); mr=$(col 3); rl=$(col 4); rw=$(col 5); rr=$(col 6)
  # Path agreement: rove's path.tum (t x y z qx qy qz qw) against MRPT's log_estimated_path.txt.
  agreement=$(paste <(grep -v '^#' "$work/rove_$variant/path.tum") "$work/mrpt_$variant/log_estimated_path.txt" | awk '
    { dx = $2 - $10; dy = $3 - $11; s += dx*dx + dy*dy; n++; ex = dx; ey = dy;
      phi = 2 * atan2($7, $8); d = phi - $12; while (d > 3.14159265) d -= 6.28318531; while (d < -3.14159265) d += 6.28318531; ea = d;
      p = sqrt(dx*dx + dy*dy); a = (d < 0 ? -d : d) * 57.29578;
      if (p > mp) mp = p; if (a > ma) ma = a; if (p > 0.05) n5++; if (a > 1) n1++ }
    END { printf "position RMSE %.4f m over %d steps; final pose differs by %.4f m, %.3f deg\n", sqrt(s/n), n, sqrt(ex*ex+ey*ey), ea*57.29578;
          printf "  largest step difference %.4f m, %.3f deg; steps beyond 5 cm: %d, beyond 1 deg: %d", mp, ma, n5 + 0, n1 + 0 }')
  echo "== $variant (median of $runs runs) =="
  printf "  mapping loop : MRPT %.3f s   rove %.3f s   speed-up %.1fx\n" "$ml" "$rl" "$(echo "$ml / $rl" | bc -l)"
  printf "  whole process: MRPT %.3f s   rove %.3f s   speed-up %.1fx\n" "$mw" "$rw" "$(echo "$mw / $rw" | bc -l)"
  printf "  peak RSS     : MRPT %d MB   rove %d MB\n" "$((mr / 1024))" "$((rr / 1024))"
  echo "  $agreement"
done
