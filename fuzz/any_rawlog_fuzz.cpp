// libFuzzer target for rove::AnyRawlogReader: format detection (rove rawlog,
// MRPT rawlog plain or gzip, CARMEN log plain or bzip2, anything else
// refused) and the reader behind it. Detection works on files, so the bytes
// are written to a scratch file that is opened and read to the end, twice:
// with the defaults (CARMEN layout #1, strict) and with CARMEN layout #2,
// skipped malformed lines and skipped unknown rove classes. Anything may be
// rejected with a rove::Error; whatever is accepted must be a valid log:
// detection agrees with the reader, every entry is non-null and passes its
// own check(), a CARMEN log gives at least one entry in the layout it was
// asked for, and the entries write out as a rove rawlog.

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>
#include <variant>

#include "rove/core/error.h"
#include "rove/io/any_rawlog.h"
#include "rove/io/rove_rawlog.h"
#include "rove/obs/gps_observation.h"
#include "rove/obs/image_observation.h"
#include "rove/obs/imu_observation.h"
#include "rove/obs/range_image_3d.h"
#include "rove/obs/range_scan_2d.h"
#include "rove/obs/rotating_scan.h"
#include "rove/serialization/memory_stream.h"

namespace {

[[noreturn]] void die(const char* what) {
  std::fprintf(stderr, "any_rawlog_fuzz: %s\n", what);
  std::abort();
}

// One scratch file per process, removed at exit.
const std::string& scratch_path() {
  static const std::string path = [] {
    std::string dir = (std::filesystem::temp_directory_path() / "rove-any-rawlog-XXXXXX").string();
    if (::mkdtemp(dir.data()) == nullptr) die("cannot create a scratch directory");
    static const std::string keep = dir;
    std::atexit([] { std::filesystem::remove_all(keep); });
    return dir + "/input";
  }();
  return path;
}

void write_scratch(const std::uint8_t* data, std::size_t size) {
  std::FILE* f = std::fopen(scratch_path().c_str(), "wb");
  if (f == nullptr) die("cannot open the scratch file");
  if (size > 0 && std::fwrite(data, 1, size, f) != size) die("cannot write the scratch file");
  if (std::fclose(f) != 0) die("cannot close the scratch file");
}

rove::AnyRawlogOptions options(bool second) {
  rove::AnyRawlogOptions o;
  o.mrpt.limits.max_length = std::uint64_t{1} << 22;
  o.rove.limits.max_length = std::uint64_t{1} << 20;
  o.rove.limits.max_nesting = 16;
  o.rove.max_entry_bytes = std::uint64_t{1} << 22;
  if (second) {
    o.rove.skip_unknown_classes = true;
    o.carmen.layout = rove::RawlogLayout::Observations;
    o.carmen.log.skip_malformed = true;
    o.carmen.log.max_line_bytes = 256;
  }
  return o;
}

void check_observation(const rove::Observation& o, bool carmen) {
  // The checks throw InvalidArgument, a rove::Error: caught by the caller
  // and turned into a failure there. MRPT and rove files may store MRPT's
  // INVALID_TIMESTAMP; CARMEN lines always carry a time.
  if (carmen && !o.timestamp.valid()) die("CARMEN observation with an invalid timestamp");
  if (const auto* s = dynamic_cast<const rove::RangeScan2D*>(&o)) s->check();
  // A range image without depth (its camera may be unset) is stored as
  // written; one with depth must pass its check.
  if (const auto* r = dynamic_cast<const rove::RangeImage3D*>(&o)) {
    if (r->depth.pixel_count() > 0) r->check();
  }
  if (const auto* g = dynamic_cast<const rove::GpsObservation*>(&o)) g->check();
  if (const auto* s = dynamic_cast<const rove::RotatingScan*>(&o)) s->check();
  if (const auto* i = dynamic_cast<const rove::ImuObservation*>(&o)) i->check();
  if (const auto* i = dynamic_cast<const rove::ImageObservation*>(&o)) i->check();
  if (o.clone() == nullptr) die("clone returned null");
}

void check_entry(const rove::RawlogEntry& e, bool carmen) {
  if (const auto* sf = std::get_if<std::shared_ptr<const rove::SensoryFrame>>(&e)) {
    if (*sf == nullptr) die("null sensory frame");
    for (const auto& o : (*sf)->observations) {
      if (o == nullptr) die("null observation in a sensory frame");
      check_observation(*o, carmen);
    }
  } else if (const auto* ob = std::get_if<std::shared_ptr<const rove::Observation>>(&e)) {
    if (*ob == nullptr) die("null observation entry");
    check_observation(**ob, carmen);
  } else {
    const auto& ac = std::get<std::shared_ptr<const rove::ActionCollection>>(e);
    if (ac == nullptr) die("null action collection");
    for (const auto& a : ac->actions) {
      if (a == nullptr) die("null action");
    }
  }
}

// ROVE_FUZZ_VERBOSE=1 prints what each input became (for replays).
bool verbose() {
  static const bool v = std::getenv("ROVE_FUZZ_VERBOSE") != nullptr;
  return v;
}

void say(const char* what, const std::string& detail) {
  if (verbose()) std::fprintf(stderr, "any_rawlog_fuzz: %s%s\n", what, detail.c_str());
}

// Entries kept for the final write, bounded so a long log stays cheap.
constexpr std::size_t kMaxKept = 64;

void run(bool second) {
  const std::string& path = scratch_path();
  bool detected = false;
  rove::RawlogFormat format = rove::RawlogFormat::Rove;
  try {
    format = rove::detect_rawlog_format(path);
    detected = true;
  } catch (const rove::Error&) {
  }
  std::vector<rove::RawlogEntry> kept;
  std::unique_ptr<rove::AnyRawlogReader> reader;
  try {
    reader = std::make_unique<rove::AnyRawlogReader>(path, options(second));
  } catch (const rove::Error& err) {
    say("refused: ", err.what());
    return;  // refused by the detection, or a malformed rove header
  }
  if (!detected) die("the reader opened a file the detection refuses");
  if (reader->format() != format) die("the reader and the detection disagree on the format");
  try {
    while (auto e = reader->next()) {
      try {
        check_entry(*e, reader->format() == rove::RawlogFormat::Carmen);
      } catch (const rove::Error& err) {
        std::fprintf(stderr, "%s\n", err.what());
        die("an accepted entry fails its check()");
      }
      if (reader->format() == rove::RawlogFormat::Carmen) {
        const bool obs = std::holds_alternative<std::shared_ptr<const rove::Observation>>(*e);
        if (obs != second) die("a CARMEN entry outside the layout asked for");
      }
      if (kept.size() < kMaxKept) kept.push_back(std::move(*e));
    }
  } catch (const rove::Error& err) {
    say("rejected part-way: ", err.what());
    return;  // rejected part-way: fine, the reader said where
  }
  if (reader->format() == rove::RawlogFormat::Carmen && reader->entries_read() == 0) {
    die("a CARMEN log was read to the end without an entry");
  }
  say("read: ", std::string(rove::to_string(reader->format())) + ", " +
                    std::to_string(reader->entries_read()) + " entries");
  // A valid log writes out as a rove rawlog (the writer refuses entries
  // its layout excludes and values it cannot store).
  try {
    rove::RoveRawlogWriterOptions wo;
    wo.layout = kept.empty() ? rove::RawlogLayout::ActionsSensoryFrames : rove::layout_of(kept);
    wo.gzip = false;
    rove::RoveRawlogWriter w(std::make_unique<rove::MemoryOutStream>("fuzz-out"), wo);
    for (const auto& e : kept) w.write(e);
    w.close();
  } catch (const rove::Error& err) {
    std::fprintf(stderr, "%s\n", err.what());
    die("entries that were read cannot be written as a rove rawlog");
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  write_scratch(data, size);
  run(false);
  run(true);
  return 0;
}
