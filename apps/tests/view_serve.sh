#!/bin/sh
# rove view serves its page on 127.0.0.1 until Ctrl-C: headless Chromium
# loads the served page (three.js from Debian, the scene as glTF) and finds
# every vertex; Ctrl-C then stops the server: exit 130 and a message.
# Usage: view_serve.sh ROVE SOURCE_DIR WORKDIR
set -u
rove=$1
source_dir=$2
work=$3
rm -rf "$work"
mkdir -p "$work"
"$rove" view --port 0 "$source_dir/data/pointcloud/bunny.pcd" "$source_dir/data/posegraph/w100.graph" \
  >"$work/stdout" 2>"$work/stderr" &
pid=$!
failures=0
url=""
for _ in $(seq 1 100); do
  url=$(sed -n 's/^serving .* on \(http:[^ ]*\) (Ctrl-C stops)$/\1/p' "$work/stdout")
  [ -n "$url" ] && break
  sleep 0.1
done
case "$url" in
  http://localhost:[0-9]*/) ;;
  *) echo "FAIL: no 'serving ... on http://localhost:PORT/' line:"; cat "$work/stdout" "$work/stderr"
     failures=$((failures + 1)) ;;
esac
if [ -n "$url" ]; then
  chromium --headless --no-sandbox --enable-unsafe-swiftshader --disable-dev-shm-usage \
    --user-data-dir="$work/profile" --virtual-time-budget=20000 --dump-dom "$url" >"$work/dom" 2>/dev/null
  # bunny.pcd has 397 points; w100.graph 60 vertices and 240 edges joining
  # 70 pairs of vertices (58 consecutive, 12 loop closures), two vertices each.
  if ! grep -q '"status":"ready","layers":4,"objects":4,"vertices":597,' "$work/dom"; then
    echo "FAIL: the served page did not show the scene:"; grep -o '<pre id="rove-stats">[^<]*' "$work/dom"
    failures=$((failures + 1))
  fi
fi
kill -INT "$pid"
wait "$pid"
status=$?
if [ "$status" -ne 130 ]; then
  echo "FAIL: exit $status after Ctrl-C, expected 130"; cat "$work/stderr"; failures=$((failures + 1))
fi
if ! grep -q "interrupted" "$work/stderr"; then
  echo "FAIL: no message after Ctrl-C:"; cat "$work/stderr"; failures=$((failures + 1))
fi
[ "$failures" -eq 0 ] && echo "rove view served the scene and stopped cleanly on Ctrl-C"
exit "$failures"
