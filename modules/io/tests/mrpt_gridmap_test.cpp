#include "rove/io/mrpt_gridmap.h"

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "rove/core/error.h"
#include "rove/serialization/memory_stream.h"

namespace rove {
namespace {

TEST(MrptGridmap, TruncatedAndLyingFilesGiveParseErrors) {
  const std::string path = ROVE_SOURCE_DIR "/modules/io/tests/data/grid_uwb_demo.gridmap.gz";
  EXPECT_NO_THROW(load_mrpt_gridmap(path));
  EXPECT_THROW(load_mrpt_gridmap(path + ".missing"), IoError);
  // A header claiming 100000 x 100000 cells in a few bytes.
  std::vector<std::uint8_t> b = {0x93};
  for (char c : std::string("COccupancyGridMap2D")) b.push_back(static_cast<std::uint8_t>(c));
  b.push_back(3);
  b.push_back(8);
  const auto put32 = [&](std::uint32_t v) {
    for (int i = 0; i < 4; ++i) b.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
  };
  const auto putf = [&](float f) {
    std::uint32_t v;
    std::memcpy(&v, &f, 4);
    put32(v);
  };
  put32(100000);
  put32(100000);
  putf(0);
  putf(5000);
  putf(0);
  putf(5000);
  putf(0.05f);
  MemoryInStream in(std::vector<std::byte>(reinterpret_cast<std::byte*>(b.data()),
                                           reinterpret_cast<std::byte*>(b.data()) + b.size()),
                    "lying.gridmap");
  InArchive ar(in);
  EXPECT_THROW(read_mrpt_gridmap(ar), ParseError);
}

}  // namespace
}  // namespace rove
