#!/usr/bin/env bash
# `rove lidar-slam` (loop closure, defaults) against MRPT 2.5.8's `icp-slam`
# (incremental, no loop closure) on the same logs, in one run: the Radish
# Intel, FR079 and ACES CARMEN logs of ../shared/datasets/radish and the
# bundled Telecom Faculty rawlog. Per log and program: whole-process wall
# and CPU time and peak RSS (/usr/bin/time -v), the real-time factor (the
# log's duration over the whole process's wall time); on ACES the relation
# error of Kümmerle et al. 2009 (`rove eval relations`). x_wall and x_cpu
# are the real-time factors over wall and CPU (user + system) time: on a
# shared machine the CPU time is the single-thread cost.
#
# MRPT's icp-slam binary runs headless on the Telecom rawlog (MRPT's
# icp-slam_demo_classic.ini) and on the CARMEN logs converted by MRPT's
# carmen2rawlog (data/icp-slam_carmen.ini, ACES read with its 50 m
# "no return" as maximum range). On those observation-only rawlogs MRPT
# 2.5.8's icp-slam never leaves its first pose ("new pose extrapolation
# failed"); the script prints how far its path went. MRPT's icp-slam
# algorithm on the CARMEN logs is therefore run as `rove icp-slam
# --arithmetic mrpt` (MRPT's path to the bit, proven by the mrpt_compat
# tests), same config: its time is rove's, its accuracy MRPT's.
#
# lidar-slam runs on one thread (its default; --threads parallelizes only
# the final refinement's alignments). Needs mrpt-apps.
# Usage: [ROVE_DATASETS_DIR=DIR] bench/run_lidar_slam_vs_mrpt.sh [LOG...]   (default: intel fr079 aces telecom)
set -euo pipefail
cd "$(dirname "$0")/.."
root=$(pwd)
data=${ROVE_DATASETS_DIR:-../shared/datasets}/radish
[ -d "$data" ] || { echo "missing $data (the Radish logs; set ROVE_DATASETS_DIR)" >&2; exit 1; }
data=$(cd "$data" && pwd)
command -v icp-slam >/dev/null || { echo "icp-slam (mrpt-apps) is not installed" >&2; exit 1; }
logs=("$@")
[ ${#logs[@]} -gt 0 ] || logs=(intel fr079 aces telecom)
telecom="$root/data/mrpt/2006-01ENE-21-SENA_Telecom_Faculty_one_loop_only.rawlog"
work=build/bench/lidar_slam
mkdir -p "$work"
cmake --preset release >/dev/null
cmake --build --preset release -j2 --target rove >/dev/null
rove=$root/build/release/apps/rove

# time_of FILE: "wall_s cpu_s rss_MB" from a /usr/bin/time -v report.
time_of() {
  awk '/Elapsed \(wall clock\)/ {n = split($NF, t, ":"); w = 0; for (i = 1; i <= n; i++) w = w * 60 + t[i]}
       /User time/ {u = $NF} /System time/ {s = $NF} /Maximum resident/ {r = $NF}
       END {printf "%.2f %.2f %d", w, u + s, r / 1024}' "$1"
}
json_number() { python3 -c 'import json, sys; print(json.load(open(sys.argv[1]))[sys.argv[2]])' "$1" "$2"; }
relations() {  # relations PATH.tum: "t ± s m, r ± s deg"
  "$rove" eval relations --json --log "$data/aces.clf.bz2" "$1" "$data/aces.relations" |
    python3 -c 'import json, math, sys; j = json.load(sys.stdin); t = j["translation_m"]; r = j["rotation_rad"]; d = 180 / math.pi
print("%.4f ± %.4f m, %.3f ± %.3f deg (%d relations)" % (t["mean"], t["std"], r["mean"] * d, r["std"] * d, j["used"]))'
}
ratio() { python3 -c 'import sys; print("%.1f" % (float(sys.argv[1]) / max(float(sys.argv[2]), 1e-3)))' "$1" "$2"; }
row() { printf "  %-32s %7s %7s %6s %8s %8s  %s\n" "$@"; }

echo "machine: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'), $(nproc) cores, load $(cut -d' ' -f1-3 /proc/loadavg)"
echo "date: $(date -u '+%Y-%m-%d %H:%M UTC')"
for log in "${logs[@]}"; do
  case $log in
    telecom) input=$telecom; extra=() ;;
    aces) input=$data/aces.clf.bz2; extra=(--max-range 50) ;;
    *) input=$data/$log.clf.bz2; extra=() ;;
  esac
  echo "== $log =="
  row program wall_s cpu_s rss_MB x_wall x_cpu "result"
  # rove lidar-slam, defaults.
  /usr/bin/time -v "$rove" lidar-slam --json --no-progress "$input" -o "$work/lidar_$log" \
    > "$work/lidar_$log.json" 2> "$work/lidar_$log.time" || [ $? -eq 3 ]
  read -r w c m <<< "$(time_of "$work/lidar_$log.time")"
  duration=$(json_number "$work/lidar_$log.json" log_duration_seconds)
  loops=$(json_number "$work/lidar_$log.json" loops_accepted)
  result="$loops loop closures"
  [ "$log" = aces ] && result="$(relations "$work/lidar_$log/path.tum")"
  row "rove lidar-slam" "$w" "$c" "$m" "$(ratio "$duration" "$w")" "$(ratio "$duration" "$c")" "$result"
  # MRPT's icp-slam binary.
  if [ "$log" = telecom ]; then
    sed -e "s|^rawlog_file *=.*|rawlog_file=$telecom|" -e 's|^SHOW_PROGRESS_3D_REAL_TIME *=.*|SHOW_PROGRESS_3D_REAL_TIME=0|' \
        -e 's|^SAVE_3D_SCENE *=.*|SAVE_3D_SCENE=0|' -e "s|^logOutput_dir *=.*|logOutput_dir=$root/$work/mrpt_$log|" \
        data/mrpt/icp-slam_demo_classic.ini > "$work/mrpt_$log.ini"
  else
    clf=$work/$log.clf
    { [ "$log" = aces ] && echo "PARAM robot_front_laser_max 50.0 nohost 0"; bzcat "$input"; } > "$clf"
    carmen2rawlog -q -w -i "$clf" -o "$work/$log.rawlog" >/dev/null 2>&1
    { cat data/icp-slam_carmen.ini
      printf '\n[MappingApplication]\nrawlog_file=%s\nrawlog_offset=0\nlogOutput_dir=%s\nLOG_FREQUENCY=0\n' \
        "$root/$work/$log.rawlog" "$root/$work/mrpt_$log"
      printf 'SAVE_POSE_LOG=0\nSAVE_3D_SCENE=0\nCAMERA_3DSCENE_FOLLOWS_ROBOT=0\nSHOW_PROGRESS_3D_REAL_TIME=0\n'
      printf 'SHOW_PROGRESS_3D_REAL_TIME_DELAY_MS=0\nSHOW_LASER_SCANS_3D=0\n'; } > "$work/mrpt_$log.ini"
  fi
  /usr/bin/time -v icp-slam "$work/mrpt_$log.ini" < /dev/null > "$work/mrpt_$log.log" 2> "$work/mrpt_$log.time"
  read -r w c m <<< "$(time_of "$work/mrpt_$log.time")"
  reach=$(awk 'NR == 1 {x0 = $2; y0 = $3} {d = sqrt(($2 - x0)^2 + ($3 - y0)^2); if (d > r) r = d} END {printf "%.2f", r}' \
    "$work/mrpt_$log/log_estimated_path.txt")
  row "MRPT icp-slam" "$w" "$c" "$m" "$(ratio "$duration" "$w")" "$(ratio "$duration" "$c")" \
    "path reaches $reach m from its start"
  # MRPT's icp-slam algorithm on the CARMEN logs: rove icp-slam --arithmetic mrpt.
  if [ "$log" != telecom ]; then
    /usr/bin/time -v "$rove" icp-slam --json --no-progress --arithmetic mrpt "${extra[@]}" data/icp-slam_carmen.ini \
      "$input" -o "$work/icp_$log" > "$work/icp_$log.json" 2> "$work/icp_$log.time" || [ $? -eq 3 ]
    read -r w c m <<< "$(time_of "$work/icp_$log.time")"
    result="no loop closure"
    [ "$log" = aces ] && result="$(relations "$work/icp_$log/path.tum")"
    row "rove icp-slam --arithmetic mrpt" "$w" "$c" "$m" "$(ratio "$duration" "$w")" "$(ratio "$duration" "$c")" "$result"
  fi
done
