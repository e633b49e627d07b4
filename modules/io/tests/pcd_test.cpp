#include "rove/io/pcd.h"

#include <cmath>
#include <cstring>
#include <random>
#include <string>

#include <gtest/gtest.h>

#include "rove/core/error.h"
#include "rove/test_data.h"

namespace rove {
namespace {

const std::string kData = test_data::bundled_file("pointcloud/");

std::vector<std::uint8_t> bytes_of(const std::string& s) { return {s.begin(), s.end()}; }

PointCloud sample_cloud(PointChannels ch, std::size_t n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-50, 50);
  PointCloud c;
  c.set_channels(ch);
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t k = c.push_back({u(rng), u(rng), u(rng)});
    if (c.has_colors())
      c.colors_mut()[k] = Rgb8{static_cast<std::uint8_t>(rng()), static_cast<std::uint8_t>(rng()),
                               static_cast<std::uint8_t>(rng())};
    if (c.has_intensity()) c.intensities_mut()[k] = u(rng);
    if (c.has_normals()) c.normals_mut()[k] = Eigen::Vector3f(u(rng), u(rng), u(rng)).normalized();
  }
  if (n > 3) c[1] = Eigen::Vector3f(std::nanf(""), 1e-40f, -0.0f);  // NaN, subnormal, -0
  if (n > 4) c[2] = Eigen::Vector3f(3.4e38f, -1.17549435e-38f, 1.0f / 3.0f);
  return c;
}

ParseError parse_error_of(const std::string& text) {
  try {
    read_pcd_from_memory(bytes_of(text), "mem.pcd");
  } catch (const ParseError& e) {
    EXPECT_EQ(e.location().source, "mem.pcd");
    return e;
  }
  ADD_FAILURE() << "no ParseError for:\n" << text.substr(0, 400);
  return ParseError({}, "");
}

TEST(Pcd, RoundTripsEveryEncodingAndChannelSetExactly) {
  const PointChannels sets[] = {PointChannels::None, PointChannels::Color, PointChannels::Intensity,
                                PointChannels::Normal,
                                PointChannels::Color | PointChannels::Intensity | PointChannels::Normal};
  for (PcdFormat f : {PcdFormat::Ascii, PcdFormat::Binary, PcdFormat::BinaryCompressed}) {
    for (PointChannels ch : sets) {
      for (std::size_t n : {0u, 1u, 7u, 500u}) {
        const PointCloud c = sample_cloud(ch, n, static_cast<unsigned>(n) + 3);
        PcdWriteOptions o;
        o.format = f;
        const auto bytes = write_pcd_to_memory(c, o);
        PcdHeader h;
        const PointCloud back = read_pcd_from_memory(bytes, "mem", &h);
        EXPECT_EQ(back, c) << "format " << int(f) << " channels " << int(ch) << " n " << n;
        EXPECT_EQ(h.points, n);
        EXPECT_EQ(h.format, f);
      }
    }
  }
}

TEST(Pcd, WritesOrganizedLayoutAndChecksIt) {
  const PointCloud c = sample_cloud(PointChannels::None, 6, 1);
  PcdWriteOptions o;
  o.width = 3;
  o.height = 2;
  PcdHeader h;
  EXPECT_EQ(read_pcd_from_memory(write_pcd_to_memory(c, o), "m", &h), c);
  EXPECT_EQ(h.width, 3u);
  EXPECT_EQ(h.height, 2u);
  o.width = 4;
  EXPECT_THROW(write_pcd_to_memory(c, o), InvalidArgument);
}

TEST(Pcd, ReadsPclStyleFieldsPaddingAndTypes) {
  // x y z as doubles, an int16 intensity, rgba as U, a padding field and a
  // 3-element descriptor that must be skipped.
  const std::string text =
      "# comment\nVERSION 0.7\nFIELDS x y z _ rgba intensity desc\nSIZE 8 8 8 4 4 2 4\n"
      "TYPE F F F U U I F\nCOUNT 1 1 1 1 1 1 3\nWIDTH 2\nHEIGHT 1\nVIEWPOINT 1 2 3 1 0 0 0\n"
      "POINTS 2\nDATA ascii\n1.5 2.5 -3.25 0 4278255360 -7 1 2 3\n\n+0.5 nan 1e-3 9 16711935 12 0 0 0\n";
  PcdHeader h;
  const PointCloud c = read_pcd_from_memory(bytes_of(text), "m", &h);
  ASSERT_EQ(c.size(), 2u);
  EXPECT_EQ(c[0], Eigen::Vector3f(1.5f, 2.5f, -3.25f));
  EXPECT_TRUE(std::isnan(c[1].y()));
  EXPECT_EQ(c[1].z(), 1e-3f);
  EXPECT_EQ(c.colors()[0], (Rgb8{0, 255, 0}));
  EXPECT_EQ(c.colors()[1], (Rgb8{255, 0, 255}));
  EXPECT_EQ(c.intensities()[0], -7.0f);
  EXPECT_FALSE(c.has_normals());
  EXPECT_EQ(h.viewpoint[1], 2.0);
  EXPECT_EQ(h.fields.size(), 7u);
  EXPECT_EQ(h.fields[6].count, 3u);

  // The same layout in binary, with the padding field present in each record.
  std::string bin =
      "VERSION 0.7\nFIELDS x y z _ rgb\nSIZE 4 4 4 4 4\nTYPE F F F U F\nCOUNT 1 1 1 1 1\nWIDTH 1\n"
      "HEIGHT 1\nPOINTS 1\nDATA binary\n";
  const float xyz[3] = {1, 2, 3};
  const std::uint32_t pad = 0xdeadbeef, rgb = 0x00102030;
  bin.append(reinterpret_cast<const char*>(xyz), 12);
  bin.append(reinterpret_cast<const char*>(&pad), 4);
  bin.append(reinterpret_cast<const char*>(&rgb), 4);
  const PointCloud b = read_pcd_from_memory(bytes_of(bin), "m");
  ASSERT_EQ(b.size(), 1u);
  EXPECT_EQ(b[0], Eigen::Vector3f(1, 2, 3));
  EXPECT_EQ(b.colors()[0], (Rgb8{0x10, 0x20, 0x30}));
}

TEST(Pcd, HeaderErrorsNameTheLineAndField) {
  const std::string ok_head = "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\n";
  auto e = parse_error_of(ok_head + "WIDTH 3\nHEIGHT 1\nPOINTS 4\nDATA ascii\n");
  EXPECT_EQ(e.location().field, "POINTS");
  EXPECT_EQ(e.location().line, 8u);
  EXPECT_EQ(parse_error_of(ok_head + "WIDTH 2\nHEIGHT 1\nPOINTS 2\nDATA ascii\n1 2 3\n").location().field, "POINTS");
  EXPECT_EQ(parse_error_of(ok_head + "WIDTH 1\nPOINTS 1\nDATA ascii\n1 2 3\n4 5 6\n").location().line, 10u);
  EXPECT_EQ(parse_error_of(ok_head + "WIDTH 1\nPOINTS 1\nDATA ascii\n1 2\n").location().field, "DATA");
  EXPECT_EQ(parse_error_of(ok_head + "WIDTH 1\nPOINTS 1\nDATA ascii\n1 2 x\n").location().field, "z");
  EXPECT_EQ(parse_error_of(ok_head + "WIDTH 1\nPOINTS 1\nDATA ascii\n1 2 1e99\n").location().field, "z");
  EXPECT_EQ(parse_error_of(ok_head + "WIDTH 1\nPOINTS 1\nDATA zip\n").location().field, "DATA");
  EXPECT_EQ(parse_error_of(ok_head + "WIDTH 1\nPOINTS 1\n").location().field, "DATA");
  EXPECT_EQ(parse_error_of(ok_head + "WIDTH -1\nDATA ascii\n").location().field, "WIDTH");
  EXPECT_EQ(parse_error_of(ok_head + "WIDTH 99999999999\nDATA ascii\n").location().field, "WIDTH");
  EXPECT_EQ(parse_error_of(ok_head + "BOGUS 1\nWIDTH 1\nDATA ascii\n").location().field, "BOGUS");
  EXPECT_EQ(parse_error_of("FIELDS x y\nSIZE 4 4\nTYPE F F\nWIDTH 0\nDATA ascii\n").location().field, "z");
  EXPECT_EQ(parse_error_of("FIELDS x y z\nSIZE 4 4\nTYPE F F F\nWIDTH 0\nDATA ascii\n").location().field, "SIZE");
  EXPECT_EQ(parse_error_of("FIELDS x y z\nSIZE 4 4 3\nTYPE F F F\nWIDTH 0\nDATA ascii\n").location().field, "SIZE");
  EXPECT_EQ(parse_error_of("FIELDS x y z\nSIZE 4 4 4\nTYPE F F D\nWIDTH 0\nDATA ascii\n").location().field, "TYPE");
  EXPECT_EQ(parse_error_of("FIELDS x y z\nSIZE 4 4 2\nTYPE F F F\nWIDTH 0\nDATA ascii\n").location().field, "z");
  EXPECT_EQ(parse_error_of("FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 0\nWIDTH 0\nDATA ascii\n").location().field,
            "COUNT");
  EXPECT_EQ(parse_error_of("FIELDS x y z x\nSIZE 4 4 4 4\nTYPE F F F F\nWIDTH 0\nDATA ascii\n").location().field, "x");
  EXPECT_EQ(parse_error_of("FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 2 1 1\nWIDTH 0\nDATA ascii\n").location().field, "x");
}

TEST(Pcd, LyingBinarySizesAreRefusedBeforeAllocating) {
  const std::string head = "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 4000000000\nHEIGHT 4000000000\n";
  auto e = parse_error_of(head + "DATA binary\n" + std::string(12, '\0'));
  EXPECT_EQ(e.location().field, "DATA");
  EXPECT_TRUE(e.location().offset.has_value());
  // binary_compressed claiming 10^7 points with a 4-byte payload
  std::string c = "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 10000000\nDATA binary_compressed\n";
  const std::uint32_t sizes[2] = {4, 120000000};
  c.append(reinterpret_cast<const char*>(sizes), 8);
  c.append("\x01\x00\x00\x00", 4);
  EXPECT_EQ(parse_error_of(c).location().field, "uncompressed_size");
  // compressed size beyond the end of the file
  std::string d = "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 1\nDATA binary_compressed\n";
  const std::uint32_t sizes2[2] = {1000, 12};
  d.append(reinterpret_cast<const char*>(sizes2), 8);
  d.append("\x0b", 1);
  d.append(std::string(12, '\0'));
  EXPECT_EQ(parse_error_of(d).location().field, "compressed_size");
  // uncompressed size that does not match the points
  std::string u = "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 2\nDATA binary_compressed\n";
  const std::uint32_t sizes3[2] = {13, 12};
  u.append(reinterpret_cast<const char*>(sizes3), 8);
  u.append("\x0b", 1);
  u.append(std::string(12, '\0'));
  EXPECT_EQ(parse_error_of(u).location().field, "uncompressed_size");
}

TEST(Pcd, EveryTruncationOfEveryEncodingIsAParseError) {
  const PointCloud c = sample_cloud(PointChannels::Color | PointChannels::Normal, 40, 9);
  for (PcdFormat f : {PcdFormat::Ascii, PcdFormat::Binary, PcdFormat::BinaryCompressed}) {
    PcdWriteOptions o;
    o.format = f;
    const auto bytes = write_pcd_to_memory(c, o);
    // An ascii file cut inside its last line may still hold a valid (shorter)
    // number: only cuts that lose a whole line are detectable there.
    std::size_t end = bytes.size();
    if (f == PcdFormat::Ascii) {
      end = bytes.size() - 1;
      while (bytes[end - 1] != '\n') --end;
    }
    for (std::size_t len = 0; len < end; len += (f == PcdFormat::Ascii ? 7 : 1)) {
      const std::span<const std::uint8_t> prefix(bytes.data(), len);
      EXPECT_THROW(read_pcd_from_memory(prefix, "cut"), ParseError) << "format " << int(f) << " len " << len;
    }
  }
}

TEST(Pcd, RandomByteCorruptionNeverCrashes) {
  const PointCloud c = sample_cloud(PointChannels::Intensity, 60, 4);
  std::mt19937 rng(5);
  for (PcdFormat f : {PcdFormat::Ascii, PcdFormat::Binary, PcdFormat::BinaryCompressed}) {
    PcdWriteOptions o;
    o.format = f;
    const auto good = write_pcd_to_memory(c, o);
    for (int t = 0; t < 300; ++t) {
      auto bad = good;
      for (int k = 0; k < 3; ++k) bad[rng() % bad.size()] = static_cast<std::uint8_t>(rng());
      try {
        read_pcd_from_memory(bad, "bad");
      } catch (const ParseError&) {
      }
    }
  }
}

TEST(Pcd, MissingFileIsAnIoError) {
  EXPECT_THROW(read_pcd(kData + "no_such_file.pcd"), IoError);
}

TEST(Pcd, LoadsTheRealDatasets) {
  PcdHeader h;
  const PointCloud r1 = read_pcd(kData + "room_scan1.pcd", &h);
  EXPECT_EQ(h.format, PcdFormat::BinaryCompressed);
  EXPECT_EQ(r1.size(), 112586u);
  // The PCL NDT tutorial reports 112,624 points for room_scan2 as well.
  EXPECT_EQ(read_pcd(kData + "room_scan2.pcd").size(), 112624u);
  const PointCloud bunny = read_pcd(kData + "bunny.pcd", &h);
  EXPECT_EQ(bunny.size(), 397u);
  EXPECT_EQ(h.version, ".5");
  EXPECT_EQ(bunny[0], Eigen::Vector3f(0.0054216f, 0.11349f, 0.040749f));
  // binary_compressed written by rove reads back identical
  EXPECT_EQ(read_pcd_from_memory(write_pcd_to_memory(r1), "m"), r1);
}

}  // namespace
}  // namespace rove
