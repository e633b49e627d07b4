#!/usr/bin/env bash
# Runs MRPT 2.5.8's pf-localization (Debian package mrpt-apps) headless on the
# bundled localization demo (localization_demo.rawlog in
# localization_demo.simplemap.gz, MRPT's localization_demo.ini: 40,000 initial
# particles in the box x in [-10, 10] m, y in [-15, -5] m, KLD-sampling, the
# likelihood field) RUNS times, and freezes what the rove tests compare
# against in modules/slam/tests/data/mrpt_pf_localization_demo.txt:
#   run step x y phi_deg sqrt_trace_cov particles ess
# one row per run and step: MRPT's printed mean pose after the step ("PDF
# estimation", 3 decimals in meters, 2 in degrees), the square root of the
# trace of its covariance (m and rad mixed, as MRPT prints it), the particle
# count after the step and the ESS before resampling (PF_stats.txt). Step 0
# is the initial PDF: MRPT does not run the filter on the log's first entry.
#
# MRPT's pf-localization seeds its random generator from the clock
# (getRandomGenerator().randomize()), so the runs differ but cannot be
# repeated. Only the GUI and logging switches of the config are changed:
# SHOW_PROGRESS_3D_REAL_TIME=false and 3DSceneFrequency=-1 (no 3D scenes or
# per-step particle files), plus absolute paths to the map and rawlog.
# Usage: tools/mrpt_pf_localization_reference/make_reference.sh [RUNS]
set -euo pipefail
cd "$(dirname "$0")/../.."
root=$(pwd)
runs=${1:-10}
out="$root/modules/slam/tests/data/mrpt_pf_localization_demo.txt"
command -v pf-localization >/dev/null || { echo "pf-localization (mrpt-apps) is not installed" >&2; exit 1; }
config=/usr/share/mrpt/config_files/pf-localization/localization_demo.ini
[ -f "$config" ] || { echo "$config is missing (Debian package mrpt-common)" >&2; exit 1; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
# shellcheck source=../../bench/pf_localization_mrpt.sh
. "$root/bench/pf_localization_mrpt.sh"
mrpt_pf_config "$config" "$root/data/mrpt/localization_demo.simplemap.gz" \
  "$root/data/mrpt/localization_demo.rawlog" "$work/out" > "$work/demo.ini"
{
  echo "# MRPT 2.5.8 pf-localization on localization_demo.rawlog with localization_demo.ini"
  echo "# (tools/mrpt_pf_localization_reference/make_reference.sh, $runs runs)"
  echo "# run step x y phi_deg sqrt_trace_cov particles ess"
} > "$work/ref.txt"
for r in $(seq 0 $((runs - 1))); do
  (cd "$work" && pf-localization demo.ini > "run.log" 2>&1)
  mrpt_pf_steps "$work/run.log" "$work/out_000_0040000/PF_stats.txt" | awk -v r="$r" '{print r, $0}' >> "$work/ref.txt"
done
cp "$work/ref.txt" "$out"
echo "wrote $out: $(grep -vc '^#' "$out") rows"
