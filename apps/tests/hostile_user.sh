#!/usr/bin/env bash
# The hostile user: every subcommand on the classes of bad input people feed a
# tool by accident or on purpose — the same file as input and output,
# directories, devices, text in place of binary, absurd sizes and counts,
# unknown commands and flags. For each case it asserts:
#   - a non-zero exit that is not a crash (1 or 2; never a signal, never 0),
#   - a message on stderr naming the culprit (file, key or flag), and no C++
#     check expression,
#   - bounded memory (an address-space limit, or ASan's RSS limit),
#   - intact inputs (checksums before and after) and no leftover temporaries.
#
#   hostile_user.sh ROVE_BINARY SOURCE_DIR WORK_DIR [--sanitized]
set -uo pipefail
rove=$1 src=$2 work=$3 sanitized=${4:-}
data=$src/data/mrpt
rm -rf "$work" && mkdir -p "$work" && cd "$work" || exit 1

# Memory: rove's own budget is 1 GB here; the process gets 3 GB of address
# space (ASan reserves terabytes of shadow, so it gets an RSS cap instead).
export ROVE_MEMORY_BUDGET=1G
if [ "$sanitized" = "--sanitized" ]; then
  export ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}hard_rss_limit_mb=3000:detect_leaks=1"
  limit_cmd=""
else
  limit_cmd="ulimit -v 3000000;"
fi

# ---- fixtures -------------------------------------------------------------
cp "$data/2006-01ENE-21-SENA_Telecom_Faculty_one_loop_only.rawlog" log.rawlog
cp "$data/icp-slam_demo_classic.ini" conf.ini
# The demo config with an occupancy grid of 1 mm cells over MRPT's default
# extent: 40,000 × 40,000 cells, far over the 1 GB budget.
{
  sed 's/^occupancyGrid_count=0/occupancyGrid_count=1/' conf.ini
  printf '\n[MappingApplication_occupancyGrid_00_creationOpts]\nresolution=0.001\n'
  printf 'min_x=-20\nmax_x=20\nmin_y=-20\nmax_y=20\n'
} > fine_grid.ini
printf 'hello world\n' > hello.txt
printf 'VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 1 0 0\nVERTEX_SE2 2 2 0 0\nEDGE_SE2 0 1 1 0 0 1 0 0 1 0 1\nEDGE_SE2 1 2 1 0 0 1 0 0 1 0 1\nEDGE_SE2 0 2 2.1 0 0 1 0 0 1 0 1\n' > graph.g2o
{
  printf '# .PCD v0.7\nVERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\n'
  printf 'WIDTH 64\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 64\nDATA ascii\n'
  for i in $(seq 0 7); do for j in $(seq 0 7); do printf '%d.%d %d.%d %d\n' $i $j $j $i $(( (i*j) % 3 )); done; done
} > cloud.pcd
cp "$src/apps/tests/data/huge_16000x16000.png" huge.png
sed 's/huge_16000x16000.png/huge.png/' "$src/apps/tests/data/huge_16000x16000.yaml" > huge.yaml
printf 'P5\n8 8\n255\n' > small.pgm && head -c 64 /dev/zero | tr '\0' '\376' >> small.pgm
printf 'image: small.pgm\nresolution: 0.1\norigin: [0, 0, 0]\nnegate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n' > small.yaml
mkdir -p adir
inputs=(log.rawlog conf.ini fine_grid.ini hello.txt graph.g2o cloud.pcd huge.png huge.yaml small.pgm small.yaml)
sum_inputs() { sha256sum "${inputs[@]}"; }
before=$(sum_inputs)

pass=0 fail=0
# expect NAME REGEX -- ARGS...: rove ARGS must fail (exit 1 or 2) printing REGEX.
expect() {
  local name=$1 regex=$2; shift 3
  local out rc
  out=$( (eval "$limit_cmd"; exec timeout -k 10 120 "$rove" "$@") 2>&1 >/dev/null </dev/null)
  rc=$?
  local why=""
  if [ $rc -eq 0 ]; then why="exit 0"
  elif [ $rc -eq 124 ]; then why="timed out (hang)"
  elif [ $rc -gt 3 ]; then why="exit $rc (crash or signal)"
  elif ! grep -Eq -- "$regex" <<<"$out"; then why="message does not match /$regex/"
  elif grep -Eq 'check failed|ROVE_CHECK|Assertion|terminate called|AddressSanitizer|runtime error|[0-9]{40}' <<<"$out"; then
    why="message shows an internal check or a raw limit"
  fi
  if [ -n "$why" ]; then
    fail=$((fail + 1)); printf 'FAIL %-34s %s\n  rove %s\n%s\n' "$name" "$why" "$*" "$(head -c 1500 <<<"$out" | sed 's/^/  | /')"
  else
    pass=$((pass + 1)); printf 'ok   %-34s %s\n' "$name" "$(head -n1 <<<"$out" | cut -c1-110)"
  fi
}

# ---- the same file as input and output -------------------------------------
expect same.rawlog_cut        'log.rawlog'  -- rawlog cut log.rawlog log.rawlog --from 0 --to 10
expect same.rawlog_decimate   'log.rawlog'  -- rawlog decimate log.rawlog ./log.rawlog --every 2
expect same.rawlog_convert    'log.rawlog'  -- rawlog convert log.rawlog log.rawlog
expect same.export_scans      'log.rawlog'  -- rawlog export-scans log.rawlog log.rawlog
expect same.export_odometry   'log.rawlog'  -- rawlog export-odometry log.rawlog log.rawlog
expect same.graph_output      'graph.g2o'   -- graph-slam -i graph.g2o -o graph.g2o
expect same.graph_plot        'graph.g2o'   -- graph-slam -i graph.g2o --plot graph.g2o
expect same.map_voronoi       'small.pgm'   -- map voronoi small.yaml -o small.pgm
expect same.map_convert       'small.yaml'  -- map convert small.yaml small.yaml
expect same.align_output      'cloud.pcd'   -- align cloud.pcd cloud.pcd -o cloud.pcd
expect same.icp_slam_outdir   'log.rawlog|conf.ini|output' -- icp-slam conf.ini log.rawlog -o log.rawlog --no-progress

# ---- directories -----------------------------------------------------------
expect dir.rawlog_info        'adir'        -- rawlog info adir
expect dir.graph              'adir'        -- graph-slam -i adir
expect dir.align              'adir'        -- align adir cloud.pcd
expect dir.config             'adir'        -- config check adir
expect dir.icp_slam_rawlog    'adir'        -- icp-slam conf.ini adir --no-progress
expect dir.map_convert        'adir'        -- map convert adir out.yaml
expect dir.map_build_config   'adir'        -- map build adir log.rawlog -o mapout

# ---- devices ---------------------------------------------------------------
expect dev.config_zero        '/dev/zero'   -- config check /dev/zero
expect dev.graph_zero         '/dev/zero'   -- graph-slam -i /dev/zero
expect dev.graph_urandom      '/dev/urandom' -- graph-slam -i /dev/urandom
expect dev.rawlog_urandom     '/dev/urandom' -- rawlog info /dev/urandom
expect dev.rawlog_zero        '/dev/zero'   -- rawlog convert /dev/zero out.rawlog
expect dev.icp_slam_config    '/dev/zero'   -- icp-slam /dev/zero log.rawlog --no-progress
expect dev.map_convert        '/dev/zero'   -- map convert /dev/zero out.yaml
expect dev.map_build_config   '/dev/urandom' -- map build /dev/urandom log.rawlog -o mapout
expect dev.align              '/dev/zero'   -- align /dev/zero cloud.pcd
expect dev.output_null        '/dev/null'   -- rawlog convert log.rawlog /dev/null

# ---- text in place of binary, and the wrong kind of file ----------------------
expect text.rawlog_info       'hello.txt'   -- rawlog info hello.txt
expect text.rawlog_g2o        'graph.g2o'   -- rawlog info graph.g2o
expect text.rawlog_pcd        'cloud.pcd'   -- rawlog export-scans cloud.pcd scans.txt
expect text.icp_slam          'hello.txt'   -- icp-slam conf.ini hello.txt --no-progress
expect text.map_build         'hello.txt'   -- map build conf.ini hello.txt -o mapout
expect text.graph             'hello.txt'   -- graph-slam -i hello.txt
expect text.align             'hello.txt'   -- align hello.txt cloud.pcd
expect text.map_convert       'hello.txt'   -- map convert hello.txt out.yaml
expect binary.config          'log.rawlog'  -- config check log.rawlog
expect binary.graph           'log.rawlog'  -- graph-slam -i log.rawlog

# ---- absurd sizes and counts -------------------------------------------------
expect size.voronoi_huge      'huge'        -- map voronoi huge.yaml -o voronoi.png
expect size.grid_resolution   'resolution'  -- map build fine_grid.ini log.rawlog -o mapout
expect size.icp_slam_resolution 'resolution' -- icp-slam fine_grid.ini log.rawlog -o slamout --no-progress
expect threads.align          'threads'     -- align cloud.pcd cloud.pcd --threads 100000
expect threads.align_negative 'threads'     -- align cloud.pcd cloud.pcd --threads -3
expect threads.graph          'threads'     -- graph-slam -i graph.g2o --threads 100000
expect threads.graph_negative 'threads' -- graph-slam -i graph.g2o --threads -1

# ---- asking for what is not there ---------------------------------------------
expect empty.cut_outside      'from|to|entries|range' -- rawlog cut log.rawlog cut.rawlog --from 100000 --to 200000
expect empty.label            'NOPE'        -- rawlog export-scans log.rawlog scans.txt --label NOPE
expect empty.graph_level      'level'       -- graph-slam -i graph.g2o --level 99
expect usage.unknown_command  'frobnicate'  -- frobnicate
expect usage.unknown_flag     'frobnicate'  -- rawlog info log.rawlog --frobnicate
expect usage.bad_number       'max-iters'   -- graph-slam -i graph.g2o --max-iters many
expect usage.zero_every       'every'       -- rawlog decimate log.rawlog dec.rawlog --every 0

# ---- what must not have happened ---------------------------------------------
after=$(sum_inputs)
if [ "$before" != "$after" ]; then
  fail=$((fail + 1)); echo "FAIL inputs changed:"; diff <(echo "$before") <(echo "$after")
else
  pass=$((pass + 1)); echo "ok   inputs intact"
fi
leftovers=$(find . -name '*.rove-tmp-*' | head)
if [ -n "$leftovers" ]; then
  fail=$((fail + 1)); echo "FAIL temporary files left behind: $leftovers"
else
  pass=$((pass + 1)); echo "ok   no temporary files left behind"
fi

echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]
