#!/usr/bin/env bash
# Range-only RBPF SLAM: `rove rbpf-slam` against MRPT 2.5.8's `rbpf-slam`
# (Debian mrpt-apps) on MRPT's simulated RO-SLAM demo (99 steps, 15
# beacons, 10 particles) with its RO-SLAM_simulatedData_MC.ini and _SOG.ini,
# each run `runs` times (rove with seeds 1..runs; MRPT draws a new seed
# every run): beacon RMSE against RO-SLAM_demo_ground_truth.txt, path RMSE
# against the simulator's true path, whole-process wall time and peak RSS.
# MRPT runs headless (SHOW_PROGRESS_IN_WINDOW=0, its logs in the work
# folder: they hold its final beacons, finalMap_*_covs.txt, and its per-step
# estimate, log_estimated_path.txt). rove's path is its most likely
# particle's (path.tum).
#
# The true path: MRPT's simul-beacons keeps the robot still for 4 steps, then
# moves it 0.2 m along a circle turning 5° a step (CPose2D(0.2 cos 5°,
# 0.2 sin 5°, 5°)); the log's odometry is that plus noise. The filter's
# step k (0-based; the log's first frame has no action and is passed over)
# sees the frame taken after max(0, k − 3) such increments.
# Needs mrpt-apps and python3. Usage: [ROVE_BIN=path/to/rove] bench/run_ro_slam_vs_mrpt.sh [runs]
set -euo pipefail
cd "$(dirname "$0")/.."
root=$(pwd)
runs=${1:-5}
command -v rbpf-slam >/dev/null || { echo "rbpf-slam (mrpt-apps) is not installed" >&2; exit 1; }
rawlog="$root/data/mrpt/RO-SLAM_demo.rawlog"
truth="$root/data/mrpt/RO-SLAM_demo_ground_truth.txt"
work=build/bench/ro_slam
mkdir -p "$work"
. bench/rove_release.sh

errors() {  # errors BEACONS_FILE PATH_FILE FORMAT -> "beacon_rmse path_rmse"
  python3 - "$truth" "$1" "$2" "$3" <<'PY'
import math, sys
truth_file, beacons_file, path_file, fmt = sys.argv[1:]
def rows(f, sep=None):
    out = []
    for line in open(f):
        line = line.strip()
        if line and line[0] not in '%#' and not line.startswith('id,'):
            out.append(line.split(sep))
    return out
true_b = {int(r[0]): (float(r[1]), float(r[2])) for r in rows(truth_file)}
if beacons_file.endswith('.csv'):
    est_b = {int(r[0]): (float(r[2]), float(r[3])) for r in rows(beacons_file, ',')}
else:
    est_b = {int(r[0]): (float(r[1]), float(r[2])) for r in rows(beacons_file)}
e = [math.dist(est_b[i], true_b[i]) ** 2 for i in true_b if i in est_b]
missing = len(true_b) - len(e)
beacon_rmse = math.sqrt(sum(e) / len(e)) if e else float('nan')
c, s, a = 0.2 * math.cos(math.radians(5)), 0.2 * math.sin(math.radians(5)), math.radians(5)
def true_pose(k):
    x = y = th = 0.0
    for _ in range(max(0, k - 3)):
        x, y, th = x + c * math.cos(th) - s * math.sin(th), y + c * math.sin(th) + s * math.cos(th), th + a
    return x, y
if fmt == 'tum':   # rove: one pose per step, in order
    est_p = [(float(r[1]), float(r[2])) for r in rows(path_file)]
else:              # MRPT log_estimated_path.txt: step x y z yaw ...
    est_p = [(float(r[1]), float(r[2])) for r in rows(path_file)]
pe = [math.dist(p, true_pose(k)) ** 2 for k, p in enumerate(est_p)]
print(f"{beacon_rmse:.5f} {math.sqrt(sum(pe) / len(pe)):.5f} {missing}")
PY
}
median() { sort -g | awk '{a[NR]=$1} END {print (NR%2 ? a[(NR+1)/2] : (a[NR/2]+a[NR/2+1])/2)}'; }
wall() { grep 'Elapsed (wall clock)' "$1" | awk '{print $NF}' | awk -F: '{print $(NF-1)*60 + $NF}'; }
rss() { awk '/Maximum resident/ {print $NF}' "$1"; }

for v in MC SOG; do
  ini=/usr/share/mrpt/config_files/rbpf-slam/RO-SLAM_simulatedData_$v.ini
  : > "$work/$v.rows"
  for i in $(seq "$runs"); do
    out="$work/mrpt_$v"
    rm -rf "$out"
    sed -e 's|^SHOW_PROGRESS_IN_WINDOW *=.*|SHOW_PROGRESS_IN_WINDOW=0|' \
        -e "s|^logOutput_dir *=.*|logOutput_dir=$root/$out|" "$ini" > "$work/mrpt_$v.ini"
    /usr/bin/time -v rbpf-slam "$work/mrpt_$v.ini" "$rawlog" > "$work/mrpt_$v.log" 2> "$work/mrpt_$v.time"
    m=$(errors "$out"/finalMap_*_covs.txt "$out/log_estimated_path.txt" mrpt)
    /usr/bin/time -v "$rove" rbpf-slam --no-progress --seed "$i" "$ini" "$rawlog" -o "$work/rove_$v" \
      > "$work/rove_$v.log" 2> "$work/rove_$v.time"
    r=$(errors "$work/rove_$v/beacons.csv" "$work/rove_$v/path.tum" tum)
    echo "$m $(wall "$work/mrpt_$v.time") $(rss "$work/mrpt_$v.time") $r $(wall "$work/rove_$v.time") $(rss "$work/rove_$v.time")" >> "$work/$v.rows"
  done
  col() { awk -v c="$1" '{print $c}' "$work/$v.rows" | median; }
  echo "== RO-SLAM_simulatedData_$v.ini on RO-SLAM_demo.rawlog (median of $runs runs; per run in $work/$v.rows) =="
  printf "  beacon RMSE : MRPT %.4f m   rove %.4f m\n" "$(col 1)" "$(col 6)"
  printf "  path RMSE   : MRPT %.4f m   rove %.4f m\n" "$(col 2)" "$(col 7)"
  printf "  wall        : MRPT %.2f s   rove %.3f s\n" "$(col 4)" "$(col 9)"
  printf "  peak RSS    : MRPT %d MB   rove %d MB\n" "$(( $(col 5) / 1024 ))" "$(( $(col 10) / 1024 ))"
  awk '{m += $3; r += $8} END {printf "  beacons missing (all runs): MRPT %d   rove %d\n", m, r}' "$work/$v.rows"
done
