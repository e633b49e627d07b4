#!/usr/bin/env bash
# `rove rbpf-slam` against MRPT 2.5.8's `rbpf-slam` (Debian mrpt-apps) on the
# bundled Telecom loop (224 scans) with MRPT's gridmapping_optimal_sampling.ini
# (25 particles, optimal sampling, 0.07 m grid), side by side in one run,
# interleaved: whole-process wall time, CPU time and peak RSS, rove with its
# default threads (every hardware thread) and with one,
# (/usr/bin/time -v). MRPT runs its config with only
# SHOW_PROGRESS_IN_WINDOW=0 (no display here) and its logs in the work
# folder ("as shipped"), and once more with its periodic logs and images off
# (LOG_FREQUENCY=0, SAVE_MAP_IMAGES=0, SAVE_3D_SCENE=0: "quiet"), its
# filter alone. rove writes its own outputs (map, path, ESS, picture).
# Needs mrpt-apps. Usage: [ROVE_BIN=path/to/rove] bench/run_rbpf_slam_vs_mrpt.sh [runs]
set -euo pipefail
cd "$(dirname "$0")/.."
root=$(pwd)
runs=${1:-3}
command -v rbpf-slam >/dev/null || { echo "rbpf-slam (mrpt-apps) is not installed" >&2; exit 1; }
rawlog="$root/data/mrpt/2006-01ENE-21-SENA_Telecom_Faculty_one_loop_only.rawlog"
ini="$root/data/mrpt/gridmapping_optimal_sampling.ini"
work=build/bench/rbpf_slam
mkdir -p "$work"
. bench/rove_release.sh

sed -e 's|^SHOW_PROGRESS_IN_WINDOW *=.*|SHOW_PROGRESS_IN_WINDOW=0|' \
    -e "s|^logOutput_dir *=.*|logOutput_dir=$root/$work/mrpt_shipped|" "$ini" > "$work/mrpt_shipped.ini"
sed -e 's|^SHOW_PROGRESS_IN_WINDOW *=.*|SHOW_PROGRESS_IN_WINDOW=0|' \
    -e 's|^LOG_FREQUENCY *=.*|LOG_FREQUENCY=0|' -e 's|^SAVE_MAP_IMAGES *=.*|SAVE_MAP_IMAGES=0|' \
    -e 's|^SAVE_3D_SCENE *=.*|SAVE_3D_SCENE=0|' \
    -e "s|^logOutput_dir *=.*|logOutput_dir=$root/$work/mrpt_quiet|" "$ini" > "$work/mrpt_quiet.ini"

median() { sort -g | awk '{a[NR]=$1} END {print (NR%2 ? a[(NR+1)/2] : (a[NR/2]+a[NR/2+1])/2)}'; }
wall() { grep 'Elapsed (wall clock)' "$1" | awk '{print $NF}' | awk -F: '{print $(NF-1)*60 + $NF}'; }
cpu() { awk '/User time/ {u=$NF} /System time/ {s=$NF} END {print u + s}' "$1"; }
rss() { awk '/Maximum resident/ {print $NF}' "$1"; }

: > "$work/times"
for i in $(seq "$runs"); do
  row=""
  for v in shipped quiet; do
    /usr/bin/time -v rbpf-slam "$work/mrpt_$v.ini" "$rawlog" > "$work/mrpt_$v.log" 2> "$work/mrpt_$v.time"
    row="$row $(wall "$work/mrpt_$v.time") $(cpu "$work/mrpt_$v.time") $(rss "$work/mrpt_$v.time")"
  done
  /usr/bin/time -v "$rove" rbpf-slam --no-progress --json --seed "$i" "$ini" "$rawlog" -o "$work/rove" \
    > "$work/rove.json" 2> "$work/rove.time"
  row="$row $(wall "$work/rove.time") $(cpu "$work/rove.time") $(rss "$work/rove.time")"
  /usr/bin/time -v "$rove" rbpf-slam --no-progress --json --threads 1 --seed "$i" "$ini" "$rawlog" \
    -o "$work/rove1" > "$work/rove1.json" 2> "$work/rove1.time"
  row="$row $(wall "$work/rove1.time") $(cpu "$work/rove1.time") $(rss "$work/rove1.time")"
  echo "$row" >> "$work/times"
done
col() { awk -v c="$1" '{print $c}' "$work/times" | median; }
msw=$(col 1); msc=$(col 2); msr=$(col 3); mqw=$(col 4); mqc=$(col 5); mqr=$(col 6)
rw=$(col 7); rc=$(col 8); rr=$(col 9); r1w=$(col 10); r1c=$(col 11)
echo "== Telecom loop, gridmapping_optimal_sampling.ini (median of $runs interleaved runs; rove with its default threads, all hardware threads, and with --threads 1) =="
printf "  whole process wall : MRPT as shipped %.2f s, quiet %.2f s   rove %.3f s   speed-up %.1fx / %.1fx\n" \
  "$msw" "$mqw" "$rw" "$(echo "$msw / $rw" | bc -l)" "$(echo "$mqw / $rw" | bc -l)"
printf "  rove --threads 1   : wall %.3f s (speed-up %.1fx / %.1fx), CPU %.3f s\n" \
  "$r1w" "$(echo "$msw / $r1w" | bc -l)" "$(echo "$mqw / $r1w" | bc -l)" "$r1c"
printf "  whole process CPU  : MRPT as shipped %.2f s, quiet %.2f s   rove %.3f s   ratio %.1fx / %.1fx\n" \
  "$msc" "$mqc" "$rc" "$(echo "$msc / $rc" | bc -l)" "$(echo "$mqc / $rc" | bc -l)"
printf "  peak RSS           : MRPT as shipped %d MB, quiet %d MB   rove %d MB   ratio %.1fx / %.1fx\n" \
  "$((msr / 1024))" "$((mqr / 1024))" "$((rr / 1024))" "$(echo "$msr / $rr" | bc -l)" "$(echo "$mqr / $rr" | bc -l)"
grep -o '"updates": [0-9]*\|"insertions": [0-9]*\|"peak_distinct_tiles": [0-9]*\|"unshared_tiles": [0-9]*\|"mapping_seconds": [0-9.e-]*' "$work/rove.json" | tr '\n' ' '
echo
