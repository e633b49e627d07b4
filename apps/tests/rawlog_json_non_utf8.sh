#!/bin/sh
# rove rawlog info --json on a file whose name is not UTF-8: the output must be
# valid JSON, with U+FFFD for the invalid byte.
# Usage: rawlog_json_non_utf8.sh ROVE LOG WORKDIR
set -eu
rove=$1
log=$2
dir=$3
name=$(printf 'caf\351.clf')
cp "$log" "$dir/$name"
out=$("$rove" rawlog info --json --no-progress "$dir/$name")
rm -f "$dir/$name"
fffd=$(printf 'caf\357\277\275.clf')
case $out in
  *"$fffd"*) ;;
  *) echo "no U+FFFD for the invalid byte in: $out" >&2; exit 1 ;;
esac
if printf '%s' "$out" | LC_ALL=C grep -q "$(printf 'caf\351')"; then
  echo "raw non-UTF-8 byte in the JSON: $out" >&2
  exit 1
fi
case $out in
  *'"issues": []'*|*'"issues":[]'*) ;;
  *) echo "no issues array: $out" >&2; exit 1 ;;
esac
echo ok
