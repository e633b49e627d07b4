// libFuzzer target for rove::read_ply_from_memory: read or reject with a
// rove::Error; a cloud that reads survives a write/read round trip.

#include <cstdint>
#include <cstdio>
#include <cstdlib>

#include "rove/core/error.h"
#include "rove/io/ply.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  rove::PointCloud c;
  try {
    c = rove::read_ply_from_memory({data, size}, "fuzz.ply");
  } catch (const rove::Error&) {
    return 0;
  }
  for (auto f : {rove::PlyFormat::Ascii, rove::PlyFormat::BinaryLittleEndian, rove::PlyFormat::BinaryBigEndian}) {
    rove::PlyWriteOptions o;
    o.format = f;
    if (!(rove::read_ply_from_memory(rove::write_ply_to_memory(c, o), "again") == c)) {
      std::fprintf(stderr, "ply_fuzz: round trip changed the cloud (format %d)\n", static_cast<int>(f));
      std::abort();
    }
  }
  return 0;
}
