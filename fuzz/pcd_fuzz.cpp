// libFuzzer target for rove::read_pcd_from_memory. Any bytes must either
// read or be rejected with a rove::Error; a cloud that reads must keep its
// channels consistent and survive a write/read round trip unchanged.

#include <cstdint>
#include <cstdio>
#include <cstdlib>

#include "rove/core/error.h"
#include "rove/io/pcd.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  rove::PointCloud c;
  try {
    c = rove::read_pcd_from_memory({data, size}, "fuzz.pcd");
  } catch (const rove::Error&) {
    return 0;
  }
  if ((c.has_colors() && c.colors().size() != c.size()) ||
      (c.has_intensity() && c.intensities().size() != c.size()) ||
      (c.has_normals() && c.normals().size() != c.size())) {
    std::fprintf(stderr, "pcd_fuzz: channel sizes disagree\n");
    std::abort();
  }
  for (auto f : {rove::PcdFormat::Ascii, rove::PcdFormat::Binary, rove::PcdFormat::BinaryCompressed}) {
    rove::PcdWriteOptions o;
    o.format = f;
    if (!(rove::read_pcd_from_memory(rove::write_pcd_to_memory(c, o), "again") == c)) {
      std::fprintf(stderr, "pcd_fuzz: round trip changed the cloud (format %d)\n", static_cast<int>(f));
      std::abort();
    }
  }
  return 0;
}
