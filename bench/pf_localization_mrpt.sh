# Helpers shared by the scripts that run MRPT 2.5.8's pf-localization
# (bench/run_pf_localization_vs_mrpt.sh, tools/mrpt_pf_localization_reference/).
# Source it; needs bash and awk.

# mrpt_pf_config CONFIG MAP RAWLOG OUT_PREFIX [KEY=VALUE...]: CONFIG on stdout
# with absolute map and rawlog paths, logOutput_dir=OUT_PREFIX, the 3D window
# off and no 3D scenes or per-step particle files (3DSceneFrequency=-1); each
# KEY=VALUE replaces that key's line in [LocalizationExperiment] (or is
# appended to it). MAP may be empty (no map_file).
mrpt_pf_config() {
  local config=$1 map=$2 rawlog=$3 prefix=$4
  shift 4
  awk -v map="$map" -v rawlog="$rawlog" -v prefix="$prefix" -v extra="$*" '
    BEGIN { n = split(extra, kv, " "); for (i = 1; i <= n; i++) { split(kv[i], p, "="); over[p[1]] = p[2]; order[i] = p[1] } }
    function flush() { for (i = 1; i <= n; i++) if (!(order[i] in done)) { print order[i] "=" over[order[i]]; done[order[i]] = 1 } }
    /^\[/ { if (sec == "LocalizationExperiment") flush(); sec = substr($0, 2, index($0, "]") - 2) }
    {
      line = $0; key = line; sub(/[ \t]*=.*/, "", key); sub(/^[ \t]+/, "", key)
      if (sec == "LocalizationExperiment" && line ~ /=/ && line !~ /^[ \t]*[#;]/) {
        if (key == "map_file") { if (map != "") print "map_file=" map; next }
        if (key == "rawlog_file") { print "rawlog_file=" rawlog; next }
        if (key == "logOutput_dir") { print "logOutput_dir=" prefix; next }
        if (key == "SHOW_PROGRESS_3D_REAL_TIME") { print "SHOW_PROGRESS_3D_REAL_TIME=false"; next }
        if (key == "3DSceneFrequency") { print "3DSceneFrequency=-1"; next }
        if (key in over) { print key "=" over[key]; done[key] = 1; next }
      }
      if (sec == "LocalizationExperiment" && line ~ /^[ \t]*#.*map_file/ && map != "") { print "map_file=" map; next }
      print
    }
    END { if (sec == "LocalizationExperiment") flush() }' "$config"
}

# mrpt_pf_steps LOG PF_STATS: one line per step from pf-localization's log
# and its PF_stats.txt: step x y phi_deg sqrt_trace_cov particles ess.
mrpt_pf_steps() {
  awk 'NR == FNR { n[FNR - 1] = $1; e[FNR - 1] = $2; next }
       /PDF estimation:/ {
         s = $0; sub(/.*PDF estimation: \(/, "", s); split(s, a, /[,)]/); sub(/deg/, "", a[3])
         t = $0; sub(/.*tr\(cov\): /, "", t)
         print step + 0, a[1], a[2], a[3], t, n[step + 0], e[step + 0]; step++ }' "$2" "$1"
}
