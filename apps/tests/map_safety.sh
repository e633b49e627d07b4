#!/usr/bin/env bash
# `rove map ...` and `rove config check` on careless input: outputs over
# inputs, sizes beyond the memory budget, configurations the commands reject.
# Each case checks the exit status, that the message names the culprit, and
# that inputs are intact.
#
#   map_safety.sh ROVE_BINARY SOURCE_DIR WORK_DIR
set -uo pipefail
rove=$1 src=$2 work=$3
rm -rf "$work" && mkdir -p "$work" && cd "$work" || exit 1

cp "$src/data/mrpt/2006-01ENE-21-SENA_Telecom_Faculty_one_loop_only.rawlog" log.rawlog
cp "$src/data/mrpt/icp-slam_demo_classic.ini" slam.ini
cp "$src/modules/io/tests/data/grid_uwb_demo.gridmap.gz" uwb.gridmap.gz
grid_ini() {  # grid_ini RESOLUTION MIN MAX
  printf '[M]\noccupancyGrid_count=1\n[M_occupancyGrid_00_creationOpts]\nresolution=%s\nmin_x=%s\nmax_x=%s\nmin_y=%s\nmax_y=%s\n' \
    "$1" "$2" "$3" "$2" "$3"
}
grid_ini 0.001 -10 10 > fine.ini
grid_ini -0.05 -10 10 > negative.ini
grid_ini 0.01 -1 1 > growing.ini
grid_ini 0.1 -10 10 > grid.ini
printf '[M]\nbeaconMap_count=1\n' > beacons.ini
sed 's/^maxIterations.*/maxIterations = many/' slam.ini > many.ini
sed 's/^maxIterations/maxIteratons/' slam.ini > typo.ini
printf '[ICP]\nmaxIterations = 80\n' | cat slam.ini - > dup.ini
dup_line=$(wc -l < dup.ini)
first_line=$(grep -n '^maxIterations' slam.ini | head -1 | cut -d: -f1)

pass=0 fail=0
# check NAME WANT_RC REGEX -- ARGS...: `rove ARGS` exits WANT_RC and its
# output (stdout and stderr) matches REGEX.
check() {
  local name=$1 want=$2 regex=$3; shift 4
  local out rc why=""
  out=$("$rove" "$@" 2>&1 </dev/null)
  rc=$?
  if [ "$rc" -ne "$want" ]; then why="exit $rc, expected $want"
  elif ! grep -Eq -- "$regex" <<<"$out"; then why="output does not match /$regex/"
  elif grep -Eq 'check failed|Assertion|terminate called' <<<"$out"; then why="an internal check"
  fi
  if [ -n "$why" ]; then
    fail=$((fail + 1)); printf 'FAIL %-32s %s\n  rove %s\n%s\n' "$name" "$why" "$*" "$(head -c 1500 <<<"$out" | sed 's/^/  | /')"
  else
    pass=$((pass + 1)); printf 'ok   %-32s %s\n' "$name" "$(grep -E -m1 -- "$regex" <<<"$out" | cut -c1-120)"
  fi
}
# intact NAME FILE SUM: FILE still has checksum SUM.
intact() {
  if [ "$(sha256sum < "$2")" = "$3" ]; then pass=$((pass + 1)); echo "ok   $1 intact"
  else fail=$((fail + 1)); echo "FAIL $1: $2 changed"; fi
}

# ---- outputs over inputs (each must be refused before anything is written) --
"$rove" map convert uwb.gridmap.gz uwb.yaml >/dev/null || { echo "FAIL setup"; exit 1; }
"$rove" map convert uwb.gridmap.gz uwb.rovegrid >/dev/null || { echo "FAIL setup"; exit 1; }
png=$(sha256sum < uwb.png) yaml=$(sha256sum < uwb.yaml) grid=$(sha256sum < uwb.rovegrid)
check voronoi_over_its_image 1 'uwb\.png.*input|input.*uwb\.png' -- map voronoi uwb.yaml -o uwb.png
intact voronoi_over_its_image uwb.png "$png"
check convert_over_its_yaml 1 'uwb\.(yaml|png)' -- map convert uwb.yaml ./uwb.yaml
intact convert_over_its_yaml uwb.yaml "$yaml"
intact convert_over_its_yaml uwb.png "$png"
check convert_over_its_grid 1 'uwb\.rovegrid' -- map convert uwb.rovegrid uwb.rovegrid
intact convert_over_its_grid uwb.rovegrid "$grid"
mkdir -p out && cp log.rawlog out/map_00_log.rawlog
log=$(sha256sum < log.rawlog)
check build_over_its_input 1 'map_00_log\.rawlog' -- map build slam.ini out/map_00_log.rawlog -o out
intact build_over_its_input out/map_00_log.rawlog "$log"
check build_out_is_a_file 1 'log\.rawlog.*output folder' -- map build slam.ini log.rawlog -o log.rawlog
intact build_out_is_a_file log.rawlog "$log"
leftovers=$(find . -name '*.rove-tmp-*')
if [ -z "$leftovers" ]; then pass=$((pass + 1)); echo "ok   no temporary files left"
else fail=$((fail + 1)); echo "FAIL temporary files left: $leftovers"; fi

# ---- memory budget: refused before allocating, naming the file or the key ----
ROVE_MEMORY_BUDGET=1M check voronoi_budget 1 'uwb\.gridmap\.gz: 700 × 650 cells .*memory budget' -- \
  map voronoi uwb.gridmap.gz -o v.png
ROVE_MEMORY_BUDGET=100M check resolution_budget 1 \
  '\[M_occupancyGrid_00_creationOpts\] resolution=0\.001 .*20000 × 20000 grid needs' -- \
  map build fine.ini log.rawlog -o fine
ROVE_MEMORY_BUDGET=2M check growing_grid_budget 1 \
  '\[M_occupancyGrid_00_creationOpts\] resolution=0\.01: growing an occupancy grid' -- \
  map build growing.ini log.rawlog -o growing
check grid_builds 0 'map 0 occupancyGrid: [0-9]+ cells' -- map build grid.ini log.rawlog -o grid

# ---- honest results ---------------------------------------------------------
check nothing_inserted 3 'warning: nothing-inserted' -- map build beacons.ini log.rawlog -o beacons
out=$("$rove" map build --json grid.ini log.rawlog -o grid 2>/dev/null)
if python3 -c 'import json,sys; d=json.load(sys.stdin); assert d["issues"] == [] and d["maps"][0]["kind"] == "occupancyGrid"' <<<"$out"; then
  pass=$((pass + 1)); echo "ok   build_json valid, issues []"
else fail=$((fail + 1)); echo "FAIL build_json"; echo "$out" | head -20; fi

# ---- config check: the commands' own validation -------------------------------
check config_valid_for_icp_slam 0 'valid for icp-slam' -- config check --for icp-slam slam.ini
check config_not_validated 0 'values not validated' -- config check slam.ini
check config_negative_resolution 1 'negative\.ini: \[M_occupancyGrid_00_creationOpts\] resolution' -- \
  config check --for map-build negative.ini
check config_typo 1 'typo\.ini: \[ICP\] maxIteratons' -- config check --for icp-slam typo.ini
check config_not_a_number 1 "many\\.ini: \\[ICP\\] maxIterations.*'many'" -- config check --for icp-slam many.ini
check config_duplicate_key 3 "dup\\.ini:$dup_line: \\[ICP\\] maxIterations repeats line $first_line" -- \
  config check --for icp-slam dup.ini
ROVE_MEMORY_BUDGET=100M check config_budget_named 1 'resolution=0\.001' -- config check --for map-build fine.ini
printf '[M]\noccupancyGrid_count=1\n[M_occupancyGrid_00_insertOpts]\nmaxOccupancyUpdateCertainty=2\n' > certainty.ini
check config_value_out_of_range 1 \
  'certainty\.ini: \[M_occupancyGrid_00_insertOpts\] maxOccupancyUpdateCertainty: line 4: 2 is outside \[0, 1\]' -- \
  config check --for map-build certainty.ini
printf '[M]\nheightMap_count=1\n[M_heightMap_00_creationOpts]\nmax_x=inf\n' > height.ini
check config_height_not_finite 1 'height\.ini: \[M_heightMap_00_creationOpts\] max_x: must be finite' -- \
  config check --for map-build height.ini
check config_dev_zero 1 '/dev/zero' -- config check /dev/zero
out=$("$rove" config check --json --for icp-slam dup.ini 2>/dev/null)
if python3 -c 'import json,sys; d=json.load(sys.stdin); assert [i["code"] for i in d["issues"]] == ["duplicate-section", "duplicate-key"] and d["files"][0]["ok"]' <<<"$out"; then
  pass=$((pass + 1)); echo "ok   config_json valid, duplicate-key issue"
else fail=$((fail + 1)); echo "FAIL config_json"; echo "$out" | head -20; fi

echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]
