// libFuzzer target for rove::CarmenLogReader. Any bytes (plain text or a
// bzip2 stream) must either read or be rejected with a rove::Error; every
// record returned must hold consistent, finite data.

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "rove/core/error.h"
#include "rove/io/carmen_log.h"

namespace {

[[noreturn]] void die(const char* what, std::size_t line) {
  std::fprintf(stderr, "carmen_fuzz: %s (line %zu)\n", what, line);
  std::abort();
}

void check_record(const rove::CarmenRecord& r) {
  const bool is_scan = r.type == rove::CarmenMessage::Flaser ||
                       r.type == rove::CarmenMessage::Rlaser ||
                       r.type == rove::CarmenMessage::RobotLaser1;
  if (is_scan != (r.scan != nullptr)) die("scan presence does not match the type", r.line);
  if ((r.type == rove::CarmenMessage::Odom) != (r.odometry != nullptr)) {
    die("odometry presence does not match the type", r.line);
  }
  if (!r.timestamp.valid()) die("invalid timestamp", r.line);
  if (!std::isfinite(r.logger_timestamp) || !std::isfinite(r.ipc_timestamp)) {
    die("non-finite timestamp field", r.line);
  }
  if (r.scan) {
    r.scan->check();
    if (r.scan->timestamp != r.timestamp) die("scan timestamp differs", r.line);
    for (float v : r.scan->ranges) {
      if (!std::isfinite(v)) die("non-finite range", r.line);
    }
    if (r.scan->size() >= 2) (void)r.scan->points_2d();
  }
}

void run(const std::string& bytes, bool skip_malformed, std::size_t max_line) {
  rove::CarmenLogOptions opts;
  opts.skip_malformed = skip_malformed;
  opts.max_line_bytes = max_line;
  try {
    rove::CarmenLogReader reader = rove::CarmenLogReader::from_memory(bytes, "<fuzz>", opts);
    rove::CarmenRecord record;
    std::size_t records = 0;
    while (reader.next(record)) {
      try {
        check_record(record);
      } catch (const rove::Error& e) {
        // A record the reader accepted must satisfy the scan's contract.
        std::fprintf(stderr, "%s\n", e.what());
        die("accepted record violates a precondition", record.line);
      }
      ++records;
    }
    const rove::CarmenLogStats& s = reader.stats();
    if (s.flaser + s.rlaser + s.odom + s.robotlaser1 + s.truepos != records) {
      die("record counts disagree", s.lines);
    }
    if (s.flaser + s.rlaser + s.odom + s.robotlaser1 + s.truepos + s.comments + s.blank + s.param +
            s.sync + s.other + s.malformed !=
        s.lines) {
      die("line counts disagree", s.lines);
    }
  } catch (const rove::Error&) {
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  run(bytes, false, std::size_t{1} << 20);
  run(bytes, true, 64);
  return 0;
}
