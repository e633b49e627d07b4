#!/usr/bin/env bash
# EKF-SLAM: rove against MRPT 2.5.8, Release build (bench preset):
#
# 1. MRPT's `kf-slam` application (mrpt-apps) on its own configs (copied to
#    the work folder with their dataset paths made absolute, so that its
#    logs are written there): does it finish?
# 2. bench_kf_slam_vs_mrpt: the filter time per step of rove's EkfSlam and
#    of MRPT's CRangeBearingKFSLAM(2D) library on each config's log, the
#    landmarks mapped and the path and landmark RMSE against the ground
#    truth, in one process.
# 3. `rove kf-slam` whole process on each config (wall time, peak RSS).
# 4. bench_kf_slam_scaling: one step (prediction + update with 10 readings)
#    against the number of landmarks N, rove and MRPT, and rove's
#    prediction alone.
# Usage: bench/run_kf_slam_vs_mrpt.sh
set -euo pipefail
cd "$(dirname "$0")/.."
configs=/usr/share/mrpt/config_files/kf-slam
list="EKF-SLAM_test.ini EKF-SLAM_6D_test.ini EKF-SLAM_6D_test_datassoc.ini EKF-SLAM_6D_noncentered_test.ini EKF-SLAM_6D_test_no_odometry.ini"
work=build/bench/kf_slam
mkdir -p "$work"
cmake --preset bench >/dev/null
cmake --build --preset bench -j2 --target rove bench_kf_slam_vs_mrpt bench_kf_slam_scaling >/dev/null
echo "machine: $(lscpu | sed -n 's/^Model name: *//p'), $(nproc) cores, load $(cut -d' ' -f1-3 /proc/loadavg)"
echo
echo "== 1. MRPT's kf-slam application"
if command -v kf-slam >/dev/null; then
  for c in $list; do
    set +e
    sed "s|\.\./\.\./datasets|/usr/share/mrpt/datasets|" "$configs/$c" >"$work/$c"
    (cd "$work" && timeout 300 kf-slam "$c" >"mrpt_$c.log" 2>&1)
    rc=$?
    set -e
    echo "kf-slam $c: exit $rc$([ $rc -eq 136 ] && echo ' (SIGFPE)')"
  done
else
  echo "kf-slam (mrpt-apps) is not installed"
fi
echo
echo "== 2. filter per step, errors against the ground truth"
args=""
for c in $list; do args="$args $configs/$c"; done
build/bench/bench/bench_kf_slam_vs_mrpt $args
echo
echo "== 3. rove kf-slam, whole process"
for c in $list; do
  /usr/bin/time -f "%e s wall, %M KB peak RSS" build/bench/apps/rove kf-slam "$configs/$c" \
    --no-progress --json -o "$work/rove_$c" >"$work/rove_$c.json" 2>"$work/rove_$c.time" || true
  echo "rove kf-slam $c: $(tail -1 "$work/rove_$c.time")"
done
echo
echo "== 4. one step against the number of landmarks"
build/bench/bench/bench_kf_slam_scaling --benchmark_min_time=0.2
