// libFuzzer target for rove's MRPT readers. The bytes are read as an MRPT
// rawlog (RawlogReader over a MemoryInStream, plain or gzip) and as a
// simple map; each must either read or be rejected with a rove::Error.
// Observations and keyframes read must pass their own consistency checks.

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <span>
#include <variant>

#include "rove/core/error.h"
#include "rove/io/mrpt_simplemap.h"
#include "rove/io/rawlog_reader.h"
#include "rove/obs/gps_observation.h"
#include "rove/obs/range_image_3d.h"
#include "rove/obs/rotating_scan.h"
#include "rove/serialization/memory_stream.h"

namespace {

[[noreturn]] void die(const char* what) {
  std::fprintf(stderr, "mrpt_rawlog_fuzz: %s\n", what);
  std::abort();
}

// Small limits keep a hostile declared length from driving the run into
// the RSS limit while still covering every reader.
rove::ArchiveLimits limits() {
  rove::ArchiveLimits l;
  l.max_length = std::uint64_t{1} << 22;
  return l;
}

void check_observation(const rove::Observation& o) {
  if (const auto* r = dynamic_cast<const rove::RangeImage3D*>(&o)) r->check();
  if (const auto* g = dynamic_cast<const rove::GpsObservation*>(&o)) g->check();
  if (const auto* s = dynamic_cast<const rove::RotatingScan*>(&o)) s->check();
  if (o.clone() == nullptr) die("clone returned null");
}

void read_rawlog(std::span<const std::byte> bytes) {
  rove::RawlogReaderOptions options;
  options.limits = limits();
  try {
    rove::RawlogReader reader(std::make_unique<rove::MemoryInStream>(bytes, "fuzz.rawlog"),
                              options);
    while (auto e = reader.next()) {
      if (const auto* sf = std::get_if<std::shared_ptr<const rove::SensoryFrame>>(&*e)) {
        if (*sf == nullptr) die("null sensory frame");
        for (const auto& o : (*sf)->observations) {
          if (o == nullptr) die("null observation");
          check_observation(*o);
        }
      } else if (const auto* ob = std::get_if<std::shared_ptr<const rove::Observation>>(&*e)) {
        if (*ob == nullptr) die("null observation entry");
        check_observation(**ob);
      } else {
        const auto& ac = std::get<std::shared_ptr<const rove::ActionCollection>>(*e);
        if (ac == nullptr) die("null action collection");
        for (const auto& a : ac->actions) {
          if (a == nullptr) die("null action");
        }
      }
    }
  } catch (const rove::Error&) {
  }
}

void read_simplemap(std::span<const std::byte> bytes) {
  try {
    rove::MemoryInStream stream(bytes, "fuzz.simplemap");
    rove::InArchive ar(stream, limits());
    const rove::SimpleMap map = rove::read_mrpt_simplemap(ar);
    for (const auto& kf : map.keyframes) {
      if (kf.frame == nullptr) die("null keyframe frame");
      for (const auto& o : kf.frame->observations) check_observation(*o);
    }
  } catch (const rove::Error&) {
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::span<const std::byte> bytes(reinterpret_cast<const std::byte*>(data), size);
  read_rawlog(bytes);
  read_simplemap(bytes);
  return 0;
}
