// 02_rawlog: stream an MRPT rawlog (the Telecom Faculty loop shipped with
// rove) one entry at a time, and count its sensory frames, odometry actions
// and laser rays. Exits non-zero if the counts differ from MRPT's
// `rawlog-edit --info` (225 sensory frames, 224 actions, 361 rays per scan).
#include <cstdio>
#include <variant>

#include "rove/io/rawlog_reader.h"
#include "rove/obs/range_scan_2d.h"
#include "rove/obs/sensory_frame.h"

int main(int argc, char** argv) {
  const char* path = argc > 1 ? argv[1] : ROVE_EXAMPLE_RAWLOG;
  rove::RawlogReader reader(path);
  int frames = 0, actions = 0, scans = 0, bad_scans = 0;
  while (auto entry = reader.next()) {
    if (std::holds_alternative<std::shared_ptr<const rove::SensoryFrame>>(*entry)) {
      ++frames;
      const auto& frame = std::get<std::shared_ptr<const rove::SensoryFrame>>(*entry);
      for (const auto& scan : frame->find_all<rove::RangeScan2D>()) {
        ++scans;
        if (scan->ranges.size() != 361) ++bad_scans;
      }
    } else if (std::holds_alternative<std::shared_ptr<const rove::ActionCollection>>(*entry)) {
      ++actions;
    }
  }
  std::printf("%s: %d sensory frames, %d actions, %d scans\n", path, frames, actions, scans);
  const bool ok = frames == 225 && actions == 224 && scans == 225 && bad_scans == 0;
  std::printf("%s\n", ok ? "matches rawlog-edit --info" : "DIFFERS FROM MRPT");
  return ok ? 0 : 1;
}
