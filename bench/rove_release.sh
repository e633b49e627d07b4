# Sourced by the bench scripts (from the repository root): sets `rove` to a
# Release build of the command line: $ROVE_BIN when set (a binary already
# built), else build/bench-release/apps/rove, configured and built here.
if [ -z "${ROVE_BIN:-}" ]; then
  cmake -S . -B build/bench-release -DCMAKE_BUILD_TYPE=Release -DROVE_BUILD_TESTS=OFF >/dev/null
  cmake --build build/bench-release --target rove -j2 >/dev/null
fi
rove=${ROVE_BIN:-build/bench-release/apps/rove}
