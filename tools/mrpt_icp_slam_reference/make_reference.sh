#!/usr/bin/env bash
# Runs MRPT 2.5.8's icp-slam (Debian package mrpt-apps) headless on the bundled
# Telecom Faculty rawlog with the bundled classic and Levenberg-Marquardt
# configs, and freezes what the rove tests compare against under
# modules/slam/tests/data/:
#   mrpt_icp_slam_<variant>_path.txt      MRPT's log_estimated_path.txt (step x y phi)
#   mrpt_icp_slam_<variant>_odometry.txt  MRPT's log_odometry_path.txt
#   mrpt_icp_slam_<variant>_counts.txt    keyframes in the final simplemap, points in the map
#                                         (classic and LM)
# Only the GUI/logging switches of the configs are changed. The "grid" variant
# is the classic config matched against a 5 cm occupancy grid
# (matchAgainstTheGrid = 1, occupancyGrid_count = 1).
set -euo pipefail
cd "$(dirname "$0")/../.."
root=$(pwd)
rawlog="$root/data/mrpt/2006-01ENE-21-SENA_Telecom_Faculty_one_loop_only.rawlog"
out="$root/modules/slam/tests/data"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
command -v icp-slam >/dev/null || { echo "icp-slam (mrpt-apps) is not installed" >&2; exit 1; }
for variant in classic LM grid; do
  src=$variant; [ "$variant" = grid ] && src=classic
  sed -e "s|^rawlog_file *=.*|rawlog_file=$rawlog|" \
      -e 's|^SHOW_PROGRESS_3D_REAL_TIME *=.*|SHOW_PROGRESS_3D_REAL_TIME=0|' \
      -e 's|^SAVE_3D_SCENE *=.*|SAVE_3D_SCENE=0|' \
      -e "s|^logOutput_dir *=.*|logOutput_dir=$work/$variant|" \
      "$root/data/mrpt/icp-slam_demo_$src.ini" > "$work/$variant.ini"
  if [ "$variant" = grid ]; then
    sed -i -e 's|^matchAgainstTheGrid *=.*|matchAgainstTheGrid = 1|' -e 's|^occupancyGrid_count *=.*|occupancyGrid_count=1|' "$work/$variant.ini"
    printf '\n[MappingApplication_occupancyGrid_00_creationOpts]\nresolution=0.05\n' >> "$work/$variant.ini"
  fi
  (cd "$work" && icp-slam "$variant.ini" > "$variant.log" 2>&1)
  cp "$work/$variant/log_estimated_path.txt" "$out/mrpt_icp_slam_${variant}_path.txt"
  cp "$work/$variant/log_odometry_path.txt" "$out/mrpt_icp_slam_${variant}_odometry.txt"
  [ "$variant" = grid ] && { echo "grid: $(wc -l < "$out/mrpt_icp_slam_grid_path.txt") steps"; continue; }
  keyframes=$(grep -c "Updating map from pose" "$work/$variant.log" || true)
  points=$(cat "$work/$variant"/_finalmaps_.txt_mrpt__maps__CSimplePointsMap_00.txt | grep -vc '^%' || true)
  printf 'keyframes %s\npoints %s\n' "$keyframes" "$points" > "$out/mrpt_icp_slam_${variant}_counts.txt"
  echo "$variant: $(wc -l < "$out/mrpt_icp_slam_${variant}_path.txt") steps, $keyframes keyframes, $points points"
done
