// libFuzzer target for rove::BagReader, rove's own reader of ROS 1 bags
// (record framing, bz2/lz4 chunks, connections, the message parsers and the
// conversion to observations). The bytes are written to a scratch file;
// an input that does not start with the "#ROSBAG V2.0" line gets that line
// and a bag header record put in front, so the fuzzer spends its time on
// the records. The file is read to the end in both layouts. It may be
// refused at opening (ParseError) and may stop early (the reader says
// where); whatever it returns must be valid: non-null entries whose
// observations pass their own check(), and a position within the file.

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>
#include <variant>

#include "rove/core/error.h"
#include "rove/obs/action_collection.h"
#include "rove/obs/image_observation.h"
#include "rove/obs/range_image_3d.h"
#include "rove/obs/range_scan_2d.h"
#include "rove/obs/sensory_frame.h"
#include "rove/ros/bag_reader.h"

namespace {

[[noreturn]] void die(const char* what) {
  std::fprintf(stderr, "ros_bag_fuzz: %s\n", what);
  std::abort();
}

const std::string& scratch_path() {
  static const std::string path = [] {
    std::string dir = (std::filesystem::temp_directory_path() / "rove-ros-bag-XXXXXX").string();
    if (::mkdtemp(dir.data()) == nullptr) die("cannot create a scratch directory");
    static const std::string keep = dir;
    std::atexit([] { std::filesystem::remove_all(keep); });
    return dir + "/input.bag";
  }();
  return path;
}

// "#ROSBAG V2.0\n" and a bag header record (op 3, no index, no data).
std::string bag_prefix() {
  std::string h;
  auto field = [&h](const std::string& name, const std::string& value) {
    const std::uint32_t n = static_cast<std::uint32_t>(name.size() + 1 + value.size());
    h.append(reinterpret_cast<const char*>(&n), 4);
    h += name + "=" + value;
  };
  field("op", std::string(1, '\x03'));
  field("index_pos", std::string(8, '\0'));
  field("conn_count", std::string(4, '\0'));
  field("chunk_count", std::string(4, '\0'));
  std::string out = "#ROSBAG V2.0\n";
  const std::uint32_t hlen = static_cast<std::uint32_t>(h.size()), dlen = 0;
  out.append(reinterpret_cast<const char*>(&hlen), 4);
  out += h;
  out.append(reinterpret_cast<const char*>(&dlen), 4);
  return out;
}

void write_scratch(const std::uint8_t* data, std::size_t size) {
  std::FILE* f = std::fopen(scratch_path().c_str(), "wb");
  if (f == nullptr) die("cannot open the scratch file");
  static const std::string magic = "#ROSBAG V2.0\n";
  if (size < magic.size() || std::memcmp(data, magic.data(), magic.size()) != 0) {
    static const std::string prefix = bag_prefix();
    if (std::fwrite(prefix.data(), 1, prefix.size(), f) != prefix.size()) die("cannot write");
  }
  if (size > 0 && std::fwrite(data, 1, size, f) != size) die("cannot write the scratch file");
  if (std::fclose(f) != 0) die("cannot close the scratch file");
}

void check_observation(const rove::Observation& o) {
  if (!o.timestamp.valid()) die("an observation without a time");
  if (const auto* s = dynamic_cast<const rove::RangeScan2D*>(&o)) s->check();
  if (const auto* r = dynamic_cast<const rove::RangeImage3D*>(&o)) r->check();
  if (const auto* i = dynamic_cast<const rove::ImageObservation*>(&o)) i->check();
}

void run(rove::RawlogLayout layout) {
  rove::BagReadOptions options;
  options.layout = layout;
  std::unique_ptr<rove::BagReader> reader;
  try {
    reader = std::make_unique<rove::BagReader>(scratch_path(), options);
  } catch (const rove::Error&) {
    return;  // not a bag
  }
  try {
    while (auto e = reader->next()) {
      try {
        if (const auto* sf = std::get_if<std::shared_ptr<const rove::SensoryFrame>>(&*e)) {
          if (*sf == nullptr || (*sf)->empty()) die("null or empty sensory frame");
          for (const auto& o : (*sf)->observations) check_observation(*o);
        } else if (const auto* ob = std::get_if<std::shared_ptr<const rove::Observation>>(&*e)) {
          if (*ob == nullptr) die("null observation");
          check_observation(**ob);
        } else if (std::get<std::shared_ptr<const rove::ActionCollection>>(*e) == nullptr) {
          die("null action collection");
        }
      } catch (const rove::Error& err) {
        std::fprintf(stderr, "%s\n", err.what());
        die("an entry that was read fails its check()");
      }
    }
  } catch (const rove::ResourceError&) {
    return;  // a declared size beyond the memory budget
  }
  if (reader->position() > std::filesystem::file_size(scratch_path())) die("read past the end");
  (void)reader->skipped();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  write_scratch(data, size);
  run(rove::RawlogLayout::ActionsSensoryFrames);
  run(rove::RawlogLayout::Observations);
  return 0;
}
