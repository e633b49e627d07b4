#include "rove/io/ply.h"

#include <cmath>
#include <random>
#include <string>

#include <gtest/gtest.h>

#include "rove/core/error.h"
#include "rove/test_data.h"

namespace rove {
namespace {

const std::string kData = test_data::bundled_file("pointcloud/");

std::vector<std::uint8_t> bytes_of(const std::string& s) { return {s.begin(), s.end()}; }

PointCloud sample(PointChannels ch, std::size_t n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-20, 20);
  PointCloud c;
  c.set_channels(ch);
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t k = c.push_back({u(rng), u(rng), u(rng)});
    if (c.has_colors()) c.colors_mut()[k] = Rgb8{static_cast<std::uint8_t>(rng()), 7, static_cast<std::uint8_t>(rng())};
    if (c.has_intensity()) c.intensities_mut()[k] = u(rng);
    if (c.has_normals()) c.normals_mut()[k] = Eigen::Vector3f(u(rng), u(rng), u(rng));
  }
  if (n > 2) c[1] = Eigen::Vector3f(std::nanf(""), 1e-42f, -0.0f);
  return c;
}

ParseError error_of(const std::string& text) {
  try {
    read_ply_from_memory(bytes_of(text), "m.ply");
  } catch (const ParseError& e) {
    EXPECT_EQ(e.location().source, "m.ply");
    return e;
  }
  ADD_FAILURE() << "no ParseError for:\n" << text.substr(0, 300);
  return ParseError({}, "");
}

TEST(Ply, RoundTripsEveryEncodingAndChannelSetExactly) {
  for (PlyFormat f : {PlyFormat::Ascii, PlyFormat::BinaryLittleEndian, PlyFormat::BinaryBigEndian})
    for (PointChannels ch : {PointChannels::None, PointChannels::Color | PointChannels::Intensity | PointChannels::Normal,
                             PointChannels::Normal})
      for (std::size_t n : {0u, 1u, 300u}) {
        const PointCloud c = sample(ch, n, static_cast<unsigned>(n));
        PlyWriteOptions o;
        o.format = f;
        EXPECT_EQ(read_ply_from_memory(write_ply_to_memory(c, o), "m"), c) << int(f) << " " << int(ch) << " " << n;
      }
}

// Regression (rove_ply_fuzz, crash-30a0600b): a binary PLY holding ±FLT_MAX
// wrote "-3.4028235e+38" in ascii, which the reader rejected as out of the
// float range (the shortest decimal of FLT_MAX is slightly above it).
TEST(Ply, AsciiFltMaxReadsBack) {
  PointCloud c;
  c.push_back({-3.4028235e38f, 3.4028235e38f, 1.0f});
  PlyWriteOptions o;
  o.format = PlyFormat::Ascii;
  EXPECT_EQ(read_ply_from_memory(write_ply_to_memory(c, o), "m"), c);
  // Still rejected: values that round to infinity as float.
  EXPECT_THROW(read_ply_from_memory(bytes_of("ply\nformat ascii 1.0\nelement vertex 1\n"
                                             "property float x\nproperty float y\nproperty float z\n"
                                             "end_header\n3.4028236e38 0 0\n"), "m"),
               ParseError);
}

TEST(Ply, SkipsOtherElementsListsAndProperties) {
  const std::string text =
      "ply\nformat ascii 1.0\ncomment hi\nelement camera 1\nproperty float f\nelement vertex 2\n"
      "property double x\nproperty double y\nproperty float z\nproperty list uchar int extra\n"
      "property float red\nproperty float green\nproperty float blue\nproperty short scalar_intensity\n"
      "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
      "3.5\n1 2 3 2 9 9 1.0 0.5 0 -4\n4 5 6 0 0.2 0.2 0.2 12\n3 0 1 0\n";
  const PointCloud c = read_ply_from_memory(bytes_of(text), "m");
  ASSERT_EQ(c.size(), 2u);
  EXPECT_EQ(c[1], Eigen::Vector3f(4, 5, 6));
  EXPECT_EQ(c.colors()[0], (Rgb8{255, 128, 0}));
  EXPECT_EQ(c.intensities()[0], -4.0f);
  // Binary big-endian with a face list after the vertices.
  std::string bin = "ply\nformat binary_big_endian 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
                    "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
  for (float v : {1.0f, -2.0f, 0.5f}) {
    std::uint32_t b;
    std::memcpy(&b, &v, 4);
    b = __builtin_bswap32(b);
    bin.append(reinterpret_cast<const char*>(&b), 4);
  }
  bin += std::string("\x03", 1) + std::string(12, '\0');
  const PointCloud b = read_ply_from_memory(bytes_of(bin), "m");
  ASSERT_EQ(b.size(), 1u);
  EXPECT_EQ(b[0], Eigen::Vector3f(1, -2, 0.5f));
}

TEST(Ply, ErrorsNameTheLineOffsetAndProperty) {
  const std::string head = "ply\nformat binary_little_endian 1.0\nelement vertex 1000000000000\nproperty float x\n"
                           "property float y\nproperty float z\nend_header\n";
  auto e = error_of(head + std::string(24, '\0'));
  EXPECT_EQ(e.location().field, "vertex");
  EXPECT_TRUE(e.location().offset.has_value());
  EXPECT_EQ(error_of("plx\n").location().line, 1u);
  EXPECT_EQ(error_of("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nend_header\n1 2\n")
                .location().field, "z");
  EXPECT_EQ(error_of("ply\nformat ascii 2.0\nend_header\n").location().field, "format");
  EXPECT_EQ(error_of("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n").location().field, "end_header");
  EXPECT_EQ(error_of("ply\nformat ascii 1.0\nelement vertex 1\nproperty quad x\nend_header\n").location().field, "x");
  auto a = error_of("ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\n"
                    "property uchar red\nend_header\n1 2 3 4\n1 2 3 256\n");
  EXPECT_EQ(a.location().field, "red");
  EXPECT_EQ(a.location().line, 10u);
  EXPECT_EQ(error_of("ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\n"
                     "end_header\n1 2 3\n").location().field, "x");
  // a list whose length runs past the end of the file
  std::string l = "ply\nformat binary_little_endian 1.0\nelement vertex 0\nproperty float x\nproperty float y\n"
                  "property float z\nelement face 1\nproperty list uint int vertex_indices\nend_header\n";
  l += std::string("\xff\xff\xff\x7f", 4);
  EXPECT_EQ(error_of(l).location().field, "vertex_indices");
  EXPECT_THROW(read_ply(kData + "missing.ply"), IoError);
}

TEST(Ply, EveryTruncationOfABinaryFileIsAParseError) {
  const PointCloud c = sample(PointChannels::Color | PointChannels::Normal, 30, 2);
  for (PlyFormat f : {PlyFormat::BinaryLittleEndian, PlyFormat::BinaryBigEndian}) {
    PlyWriteOptions o;
    o.format = f;
    const auto bytes = write_ply_to_memory(c, o);
    for (std::size_t len = 0; len < bytes.size(); ++len)
      EXPECT_THROW(read_ply_from_memory(std::span<const std::uint8_t>(bytes.data(), len), "cut"), ParseError) << len;
  }
}

TEST(PlyDatasets, LoadsTheSmallGicpPair) {
  const PointCloud s = read_ply(test_data::shared_dataset("pointcloud/small_gicp_source.ply"));
  const PointCloud t = read_ply(test_data::shared_dataset("pointcloud/small_gicp_target.ply"));
  EXPECT_EQ(s.size(), 69792u);
  EXPECT_GT(t.size(), 60000u);
  EXPECT_TRUE(s.has_intensity());
  EXPECT_EQ(s.count_finite(), s.size());
  EXPECT_EQ(read_ply_from_memory(write_ply_to_memory(s), "m"), s);
}

}  // namespace
}  // namespace rove
