#!/bin/sh
# rove icp-slam --json with a config whose file name is not UTF-8: stdout and
# summary.json must be valid JSON, with U+FFFD for the invalid byte.
# Usage: icp_slam_json_non_utf8.sh ROVE CONFIG RAWLOG WORKDIR
set -eu
rove=$1
config=$2
rawlog=$3
dir=$4
mkdir -p "$dir"
name=$(printf 'conf\351.ini')
cp "$config" "$dir/$name"
out=$("$rove" icp-slam --json --no-progress --max-steps 5 "$dir/$name" "$rawlog" -o "$dir/out")
summary=$(cat "$dir/out/summary.json")
rm -f "$dir/$name"
fffd=$(printf 'conf\357\277\275.ini')
for text in "$out" "$summary"; do
  case $text in
    *"$fffd"*) ;;
    *) echo "no U+FFFD for the invalid byte in: $text" >&2; exit 1 ;;
  esac
  if printf '%s' "$text" | LC_ALL=C grep -q "$(printf 'conf\351')"; then
    echo "raw non-UTF-8 byte in the JSON: $text" >&2
    exit 1
  fi
  case $text in
    *'"issues": ['*) ;;
    *) echo "no issues array: $text" >&2; exit 1 ;;
  esac
done
echo ok
