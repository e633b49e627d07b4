#!/usr/bin/env bash
# `rove pf-localization` against MRPT 2.5.8's `pf-localization` (mrpt-apps)
# on the same inputs, side by side in one run, Release build (bench preset):
#
# 1. The localization demo: localization_demo.rawlog in
#    localization_demo.simplemap.gz with MRPT's localization_demo.ini
#    unchanged (40,000 initial particles in the box x [-10, 10] m,
#    y [-15, -5] m, KLD-sampling up to 40,000, the likelihood field), RUNS
#    runs each, interleaved: whole-process wall and CPU (user + system)
#    time and peak RSS (/usr/bin/time -v), the filter loop alone (MRPT: its
#    "Total execution time"; rove: filter_seconds of its summary), and the
#    agreement of the two mean paths once both are concentrated.
# 2. Global localization on the same log: particles uniform over the free
#    cells of the whole map (rove: --global, with and without --recovery
#    0.001,0.2; MRPT: init_PDF_mode=0 with the box set to the whole grid,
#    x [-38, 37] m, y [-21, 10.02] m), GLOBAL runs each (rove: seeds
#    0..GLOBAL-1; MRPT seeds itself from the clock). A run succeeds when its
#    final estimate (step 36) lies within 0.3 m and 5 deg of MRPT's tracked
#    estimate (the median of the frozen reference runs,
#    modules/slam/tests/data/mrpt_pf_localization_demo.txt) and the filter
#    is concentrated (rove: its summary says converged; MRPT: sqrt(trace
#    cov) < 0.2 as it prints it).
# 3. Range-only localization on MRPT's UWB log (three beacons, 342 steps)
#    with modules/slam/tests/data/uwb_pf_localization.ini (MRPT's
#    ro-localization-demo.ini for the UWB beacons): position RMSE against
#    the log's ground truth, RO runs each.
# 4. One weighting step of 40,000 particles with the likelihood field
#    (bench_pf_localization_vs_mrpt: particles·rays per second).
#
# MRPT runs headless (SHOW_PROGRESS_3D_REAL_TIME=false) without 3D scenes or
# per-step particle files (3DSceneFrequency=-1); it still writes its
# per-step statistics and initial particles. rove writes its usual outputs
# (path, odometry, per-step statistics, three particle snapshots, map
# picture, summary).
# Usage: bench/run_pf_localization_vs_mrpt.sh [RUNS [GLOBAL [RO [THREADS]]]]
#        (defaults 5 50 5 1; 0 skips a part)
set -euo pipefail
cd "$(dirname "$0")/.."
root=$(pwd)
runs=${1:-5}
global_runs=${2:-50}
ro_runs=${3:-5}
threads=${4:-1}
command -v pf-localization >/dev/null || { echo "pf-localization (mrpt-apps) is not installed" >&2; exit 1; }
datasets=/usr/share/mrpt/datasets
config=/usr/share/mrpt/config_files/pf-localization/localization_demo.ini
[ -f "$config" ] || { echo "$config is missing (mrpt-common)" >&2; exit 1; }
work=build/bench/pf_localization
mkdir -p "$work"
cmake --preset bench >/dev/null
cmake --build build/bench --target rove bench_pf_localization_vs_mrpt -j2 >/dev/null
rove=build/bench/apps/rove
# shellcheck source=pf_localization_mrpt.sh
. bench/pf_localization_mrpt.sh

median() { sort -g | awk '{a[NR]=$1} END {print (NR%2 ? a[(NR+1)/2] : (a[NR/2]+a[NR/2+1])/2)}'; }
wall() { grep 'Elapsed (wall clock)' "$1" | awk '{print $NF}' | awk -F: '{print $(NF-1)*60 + $NF}'; }
cpu() { awk '/User time|System time/ {s += $NF} END {print s}' "$1"; }
rss() { awk '/Maximum resident/ {print $NF}' "$1"; }
json_number() { grep -o "\"$2\": [-0-9.e]*" "$1" | head -1 | awk '{print $2}'; }

lscpu | awk -F: '/Model name/ {gsub(/^ +/, "", $2); print "machine: " $2}'
echo "cores: $(nproc); load average at the start: $(cut -d' ' -f1-3 /proc/loadavg)"

# --- 1. The demo ------------------------------------------------------------
if [ "$runs" -gt 0 ]; then
  mrpt_pf_config "$config" "$datasets/localization_demo.simplemap.gz" \
    "$datasets/localization_demo.rawlog" "$root/$work/mrpt" > "$work/mrpt.ini"
  : > "$work/times"
  for i in $(seq "$runs"); do
    (cd "$work" && /usr/bin/time -v pf-localization mrpt.ini > mrpt.log 2> mrpt.time)
    mrpt_loop=$(grep -o 'Total execution time: [0-9.]*' "$work/mrpt.log" | awk '{print $NF}')
    /usr/bin/time -v "$rove" pf-localization "$config" --json --no-progress --seed "$i" \
      --threads "$threads" -o "$work/rove" > "$work/rove.json" 2> "$work/rove.time" || true
    echo "$mrpt_loop $(wall "$work/mrpt.time") $(cpu "$work/mrpt.time") $(rss "$work/mrpt.time")" \
      "$(json_number "$work/rove.json" filter_seconds) $(wall "$work/rove.time")" \
      "$(cpu "$work/rove.time") $(rss "$work/rove.time")" >> "$work/times"
  done
  col() { awk -v c="$1" '{print $c}' "$work/times" | median; }
  ml=$(col 1); mw=$(col 2); mc=$(col 3); mr=$(col 4); rl=$(col 5); rw=$(col 6); rc=$(col 7); rr=$(col 8)
  # Agreement of the last runs' paths at the steps where both are
  # concentrated (MRPT: sqrt(trace cov) < 0.2; rove: converged). MRPT's step
  # k and rove's step k are both the estimate after the log's k-th step.
  mrpt_pf_steps "$work/mrpt.log" "$work/mrpt_000_0040000/PF_stats.txt" > "$work/mrpt_steps.txt"
  agreement=$(awk 'NR == FNR { if ($5 < 0.2) { x[$1] = $2; y[$1] = $3; p[$1] = $4 } next }
    /^#/ { next }
    { k = $1; if (!(k in x) || $8 != 1) next
      dx = $3 - x[k]; dy = $4 - y[k]; d = $5 * 57.29578 - p[k]
      while (d > 180) d -= 360; while (d < -180) d += 360
      e = sqrt(dx*dx + dy*dy); s += e*e; n++; if (e > me) me = e; if (d < 0) d = -d; if (d > md) md = d }
    END { printf "%d common converged steps: position RMSE %.3f m, largest %.3f m, largest heading difference %.2f deg", n, sqrt(s/n), me, md }' \
    "$work/mrpt_steps.txt" "$work/rove/steps.txt")
  echo "== 1. localization_demo.ini (median of $runs interleaved runs; rove --threads $threads) =="
  printf "  filter loop        : MRPT %.3f s   rove %.3f s   MRPT/rove %.1fx\n" "$ml" "$rl" "$(echo "$ml / $rl" | bc -l)"
  printf "  whole process, wall: MRPT %.3f s   rove %.3f s   MRPT/rove %.1fx\n" "$mw" "$rw" "$(echo "$mw / $rw" | bc -l)"
  printf "  whole process, CPU : MRPT %.3f s   rove %.3f s   MRPT/rove %.1fx\n" "$mc" "$rc" "$(echo "$mc / $rc" | bc -l)"
  printf "  peak RSS           : MRPT %d MB   rove %d MB\n" "$((mr / 1024))" "$((rr / 1024))"
  echo "  agreement (last run): $agreement"
fi

# --- 2. Global localization -------------------------------------------------
if [ "$global_runs" -gt 0 ]; then
  mrpt_pf_config "$config" "$datasets/localization_demo.simplemap.gz" \
    "$datasets/localization_demo.rawlog" "$root/$work/global_mrpt" \
    init_PDF_min_x=-38 init_PDF_max_x=37 init_PDF_min_y=-21 init_PDF_max_y=10.02 > "$work/global_mrpt.ini"
  # The reference final pose: median over MRPT's frozen runs of step 36.
  read -r gx gy gphi < <(awk '!/^#/ && $2 == 36 { x[n] = $3; y[n] = $4; p[n] = $5; n++ }
    function med(a,   i, j, t) { for (i = 0; i < n; i++) for (j = i + 1; j < n; j++) if (a[j] < a[i]) { t = a[i]; a[i] = a[j]; a[j] = t }
                                 return n % 2 ? a[(n - 1) / 2] : (a[n / 2 - 1] + a[n / 2]) / 2 }
    END { print med(x), med(y), med(p) }' modules/slam/tests/data/mrpt_pf_localization_demo.txt)
  near() {  # x y phi_deg -> 1 if within 0.3 m and 5 deg of the reference
    awk -v x="$1" -v y="$2" -v p="$3" -v gx="$gx" -v gy="$gy" -v gp="$gphi" 'BEGIN {
      d = p - gp; while (d > 180) d -= 360; while (d < -180) d += 360; if (d < 0) d = -d
      print (sqrt((x - gx)^2 + (y - gy)^2) <= 0.3 && d <= 5) ? 1 : 0 }'
  }
  rove_found() {  # JSON summary -> 1 if converged on the robot
    local conv fx fy fp
    conv=$(grep -c '"termination": "converged"' "$1" || true)
    [ "$conv" = 1 ] || { echo 0; return; }
    fx=$(tr -d '\n ' < "$1" | grep -o '"final_pose":{[^}]*}' | grep -o '"x":[-0-9.e]*' | cut -d: -f2)
    fy=$(tr -d '\n ' < "$1" | grep -o '"final_pose":{[^}]*}' | grep -o '"y":[-0-9.e]*' | cut -d: -f2)
    fp=$(tr -d '\n ' < "$1" | grep -o '"final_pose":{[^}]*}' | grep -o '"phi":[-0-9.e]*' | cut -d: -f2)
    near "$fx" "$fy" "$(awk -v p="$fp" 'BEGIN {print p * 57.29578}')"
  }
  with=0; without=0; mrpt_ok=0; steps=""
  : > "$work/global_runs.txt"
  for s in $(seq 0 $((global_runs - 1))); do
    "$rove" pf-localization "$config" --global --recovery 0.001,0.2 --json --no-progress --seed "$s" \
      --threads "$threads" -o "$work/global_rove" > "$work/global_with.json" 2>/dev/null || true
    "$rove" pf-localization "$config" --global --json --no-progress --seed "$s" \
      --threads "$threads" -o "$work/global_rove" > "$work/global_without.json" 2>/dev/null || true
    a=$(rove_found "$work/global_with.json"); b=$(rove_found "$work/global_without.json")
    with=$((with + a)); without=$((without + b))
    [ "$a" = 1 ] && steps="$steps $(json_number "$work/global_with.json" converged_step)"
    (cd "$work" && pf-localization global_mrpt.ini > global_mrpt.log 2>&1) || true
    read -r _ mx my mp mt _ < <(mrpt_pf_steps "$work/global_mrpt.log" "$work/global_mrpt_000_0040000/PF_stats.txt" | tail -1)
    m=$(awk -v t="$mt" 'BEGIN { print (t < 0.2) ? 1 : 0 }')
    [ "$m" = 1 ] && m=$(near "$mx" "$my" "$mp")
    mrpt_ok=$((mrpt_ok + m))
    echo "run $s: rove with recovery $a, without $b; MRPT $m" >> "$work/global_runs.txt"
  done
  echo "== 2. global localization ($global_runs runs, 40,000 initial particles over the whole free space) =="
  echo "  rove --recovery 0.001,0.2: $with of $global_runs on the robot at the last step (converged at steps:$steps)"
  echo "  rove without recovery    : $without of $global_runs"
  echo "  MRPT pf-localization     : $mrpt_ok of $global_runs"
fi

# --- 3. Range-only localization ---------------------------------------------
if [ "$ro_runs" -gt 0 ]; then
  truth=$datasets/uwb_ro-localization_demo_GT.txt
  ro_config=modules/slam/tests/data/uwb_pf_localization.ini
  mrpt_pf_config "$ro_config" "" "$datasets/uwb_ro-localization_demo.rawlog" \
    "$root/$work/ro_mrpt" > "$work/ro_mrpt.ini"
  # rmse FILE COLUMN_OF_STEP COLUMN_OF_X: position RMSE of `step x y` rows
  # (the truth is in the odometry frame, at (2, 4) m in the beacons' frame).
  rmse() {
    awk -v cs="$2" -v cx="$3" 'NR == FNR { gx[$1] = $2 + 2; gy[$1] = $3 + 4; next } /^#/ { next }
      ($cs in gx) { dx = $cx - gx[$cs]; dy = $(cx + 1) - gy[$cs]; s += dx*dx + dy*dy; n++ }
      END { printf "%.3f", sqrt(s / n) }' "$truth" "$1"
  }
  rove_all=""; mrpt_all=""
  for s in $(seq 0 $((ro_runs - 1))); do
    "$rove" pf-localization "$ro_config" --no-progress --seed "$s" --threads "$threads" \
      -o "$work/ro_rove" > /dev/null 2>&1 || true
    rove_all="$rove_all $(rmse "$work/ro_rove/steps.txt" 1 3)"
    (cd "$work" && pf-localization ro_mrpt.ini > ro_mrpt.log 2>&1) || true
    mrpt_pf_steps "$work/ro_mrpt.log" "$work/ro_mrpt_000_0040000/PF_stats.txt" > "$work/ro_mrpt_steps.txt"
    mrpt_all="$mrpt_all $(rmse "$work/ro_mrpt_steps.txt" 1 2)"
  done
  echo "== 3. range-only localization, UWB log ($ro_runs runs each, position RMSE vs ground truth, m) =="
  echo "  rove pf-localization:$rove_all (median $(echo "$rove_all" | tr ' ' '\n' | grep . | median))"
  echo "  MRPT pf-localization:$mrpt_all (median $(echo "$mrpt_all" | tr ' ' '\n' | grep . | median))"
fi

# --- 4. One weighting step --------------------------------------------------
echo "== 4. weighting 40,000 particles with the likelihood field, one scan =="
build/bench/bench/bench_pf_localization_vs_mrpt --benchmark_repetitions=5 \
  --benchmark_report_aggregates_only=true 2>&1 | grep -E 'largest|median' || true
