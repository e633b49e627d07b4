// Occupancy grids in files: PNG/PGM images, ROS map.yaml, rove's binary
// format; hostile input (truncations, lying sizes) must give ParseError.

#include <gtest/gtest.h>
#include <zlib.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>

#include "rove/core/error.h"
#include "rove/io/file_bytes.h"
#include "rove/io/gray_image.h"
#include "rove/io/grid_binary.h"
#include "rove/io/grid_image.h"
#include "rove/io/mrpt_gridmap.h"
#include "rove/io/ros_map_yaml.h"
#include "rove/serialization/memory_stream.h"
#include "rove/test_data.h"

namespace rove {
namespace {

namespace fs = std::filesystem;
const std::string kData = ROVE_SOURCE_DIR "/modules/io/tests/data/";

// A fresh directory of this test's own: ctest runs the tests of this file
// as separate processes at once, so the name carries the test's name (a
// shared "hand" directory let the HandWrittenRosMap cases overwrite each
// other's map.yaml).
fs::path temp_dir(const std::string& name) {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  const std::string test = info ? std::string(info->test_suite_name()) + "." + info->name() : "none";
  const fs::path d = fs::temp_directory_path() / ("rove_grid_io_" + name + "_" + test);
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

void write_text(const fs::path& p, const std::string& s) {
  std::ofstream f(p, std::ios::binary);
  f << s;
}

std::span<const std::uint8_t> bytes_of(const std::string& s) {
  return {reinterpret_cast<const std::uint8_t*>(s.data()), s.size()};
}

GrayImage random_image(std::uint32_t w, std::uint32_t h, unsigned seed) {
  std::mt19937 rng(seed);
  GrayImage img{w, h, std::vector<std::uint8_t>(static_cast<std::size_t>(w) * h)};
  for (auto& p : img.pixels) p = static_cast<std::uint8_t>(rng() & 0xFF);
  return img;
}

OccupancyGrid random_grid(unsigned seed) {
  OccupancyGrid g(-3.2f, 4.1f, -1.05f, 2.3f, 0.05f);
  std::mt19937 rng(seed);
  for (auto& c : g.mutable_cells()) c = static_cast<std::int8_t>(static_cast<int>(rng() % 256) - 128);
  // Keep a share of exact classes so that every class occurs.
  for (std::size_t i = 0; i < g.cells().size(); i += 7) g.mutable_cells()[i] = 0;
  g.set_empty(false);
  return g;
}

enum class Cls { Free, Occupied, Unknown };
Cls class_of(float p_free, double occ_t = 0.65, double free_t = 0.196) {
  const double occ = 1.0 - static_cast<double>(p_free);
  return occ > occ_t ? Cls::Occupied : occ < free_t ? Cls::Free : Cls::Unknown;
}

// Sets bytes [at, at+4) to big-endian v and fixes the CRC of the chunk
// whose type starts at `chunk_type_at` with data length `len`.
void patch_png_u32(std::vector<std::uint8_t>& png, std::size_t at, std::uint32_t v,
                   std::size_t chunk_type_at, std::size_t len) {
  for (int i = 0; i < 4; ++i) png[at + static_cast<std::size_t>(i)] = static_cast<std::uint8_t>(v >> (24 - 8 * i));
  const uLong crc = crc32(0L, png.data() + chunk_type_at, static_cast<uInt>(len + 4));
  const std::size_t c = chunk_type_at + 4 + len;
  for (int i = 0; i < 4; ++i) png[c + static_cast<std::size_t>(i)] = static_cast<std::uint8_t>(crc >> (24 - 8 * i));
}

// ------------------------------------------------------------- images ----

TEST(GrayImage, PngRoundTripIsExact) {
  for (auto [w, h] : {std::pair{1u, 1u}, {37u, 23u}, {300u, 2u}}) {
    const GrayImage img = random_image(w, h, w * 31 + h);
    EXPECT_EQ(decode_png(encode_png(img), "rt.png"), img);
    EXPECT_EQ(decode_gray_image(encode_png(img), "rt.png"), img);
  }
}

TEST(GrayImage, PgmRoundTripIsExact) {
  const GrayImage img = random_image(41, 17, 5);
  const auto bytes = encode_pgm(img);
  EXPECT_EQ(std::string(bytes.begin(), bytes.begin() + 13), "P5\n41 17\n255\n");
  EXPECT_EQ(decode_pgm(bytes, "rt.pgm"), img);
}

TEST(GrayImage, PgmAsciiCommentsAndMaxval) {
  const std::string p2 = "P2\n# a comment\n3 2 # trailing\n15\n0 15 7\n8\n1 2\n";
  const GrayImage img = decode_pgm(bytes_of(p2), "a.pgm");
  ASSERT_EQ(img.width, 3u);
  ASSERT_EQ(img.height, 2u);
  // round(255 v / 15) = 17 v.
  EXPECT_EQ(img.pixels, (std::vector<std::uint8_t>{0, 255, 119, 136, 17, 34}));
  // 16-bit binary samples, big-endian.
  std::string p5 = "P5 2 1 65535\n";
  p5 += std::string("\xff\xff\x80\x00", 4);
  const GrayImage wide = decode_pgm(bytes_of(p5), "w.pgm");
  EXPECT_EQ(wide.pixels, (std::vector<std::uint8_t>{255, 128}));
}

TEST(GrayImage, PngColorBecomesChannelAverage) {
  // A 2 x 1 RGB PNG assembled by hand (IHDR color type 2, zlib IDAT):
  // map_server's gray is the integer average of R, G, B.
  const std::uint8_t raw[] = {0, 30, 60, 90, 255, 0, 0};  // filter 0, (30,60,90), (255,0,0)
  std::vector<std::uint8_t> z(64);
  uLongf zn = z.size();
  ASSERT_EQ(compress(z.data(), &zn, raw, sizeof raw), Z_OK);
  z.resize(zn);
  std::vector<std::uint8_t> png = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  const auto chunk = [&png](const char* type, const std::vector<std::uint8_t>& data) {
    const auto n = static_cast<std::uint32_t>(data.size());
    for (int i = 0; i < 4; ++i) png.push_back(static_cast<std::uint8_t>(n >> (24 - 8 * i)));
    const std::size_t start = png.size();
    png.insert(png.end(), type, type + 4);
    png.insert(png.end(), data.begin(), data.end());
    const uLong crc = crc32(0L, png.data() + start, static_cast<uInt>(data.size() + 4));
    for (int i = 0; i < 4; ++i) png.push_back(static_cast<std::uint8_t>(crc >> (24 - 8 * i)));
  };
  chunk("IHDR", {0, 0, 0, 2, 0, 0, 0, 1, 8, 2, 0, 0, 0});
  chunk("IDAT", z);
  chunk("IEND", {});
  const GrayImage img = decode_png(png, "rgb.png");
  EXPECT_EQ(img.pixels, (std::vector<std::uint8_t>{60, 85}));
}

// The fuzz seeds, written by hand (fuzz/corpus/grid_io/): every PNG
// variant the decoder converts, with known pixels.
TEST(GrayImage, DecodesEveryPngKind) {
  const std::string dir = ROVE_SOURCE_DIR "/fuzz/corpus/grid_io/";
  const auto px = [&](const std::string& name) { return read_gray_image(dir + name).pixels; };
  using V = std::vector<std::uint8_t>;
  EXPECT_EQ(px("gray8.png"), (V{0, 128, 255, 10, 30, 60}));  // row 1 uses the Sub filter
  EXPECT_EQ(px("interlaced.png"), (V{10, 20, 30, 40}));      // Adam7
  EXPECT_EQ(px("palette.png"), (V{0, 60}));                  // (30, 60, 90) averaged
  EXPECT_EQ(px("gray16.png"), (V{0x12, 0xAB}));              // high byte kept
  EXPECT_EQ(px("gray1.png"), (V{255, 0, 255}));              // 1-bit scaled to 8
  EXPECT_EQ(px("rgba.png"), (V{60}));                        // alpha ignored
  EXPECT_EQ(px("p5_16.pgm"), (V{255, 128}));
  EXPECT_EQ(px("p2.pgm"), (V{0, 255, 119, 136, 17, 34}));
}

TEST(GrayImage, EveryTruncatedPngIsAParseError) {
  const auto png = encode_png(random_image(19, 11, 3));
  for (std::size_t n = 0; n < png.size(); ++n) {
    EXPECT_THROW((void)decode_png({png.data(), n}, "cut.png"), ParseError) << "prefix " << n;
  }
}

TEST(GrayImage, EveryTruncatedPgmIsAParseError) {
  const auto pgm = encode_pgm(random_image(7, 5, 4));
  for (std::size_t n = 0; n < pgm.size(); ++n) {
    EXPECT_THROW((void)decode_pgm({pgm.data(), n}, "cut.pgm"), ParseError) << "prefix " << n;
  }
  // ASCII: a prefix that only loses the final newline is a complete image.
  const std::string p2 = "P2\n3 2\n255\n10 200 3\n40 50 6\n";
  for (std::size_t n = 0; n + 1 < p2.size(); ++n) {
    EXPECT_THROW((void)decode_pgm(bytes_of(p2.substr(0, n)), "cut.pgm"), ParseError) << "prefix " << n;
  }
}

TEST(GrayImage, LyingPgmSizeIsRejectedBeforeAllocating) {
  try {
    (void)decode_pgm(bytes_of("P5\n16000 16000\n255\nabc"), "lie.pgm");
    FAIL() << "no error";
  } catch (const ParseError& e) {
    EXPECT_EQ(e.location().source, "lie.pgm");
    EXPECT_EQ(e.location().field, "image data");
    EXPECT_NE(e.problem().find("256000000 bytes"), std::string::npos) << e.problem();
  }
  EXPECT_THROW((void)decode_pgm(bytes_of("P5\n60000 60000\n255\n"), "big.pgm"), ParseError);
  EXPECT_THROW((void)decode_pgm(bytes_of("P5\n70000 1\n255\n"), "big.pgm"), ParseError);
  EXPECT_THROW((void)decode_pgm(bytes_of("P5\n99999999999999999999 1\n255\n"), "big.pgm"), ParseError);
  EXPECT_THROW((void)decode_pgm(bytes_of("P2\n1000 1000\n255\n1 2 3\n"), "lie2.pgm"), ParseError);
  EXPECT_THROW((void)decode_pgm(bytes_of("P5\n2 1\n100\n\x01\xff"), "over.pgm"), ParseError);
  EXPECT_THROW((void)decode_pgm(bytes_of("P5\n0 1\n255\n"), "zero.pgm"), ParseError);
  EXPECT_THROW((void)decode_pgm(bytes_of("P5\n1 1\n0\n\x00"), "maxval.pgm"), ParseError);
  ImageLimits small;
  small.max_pixels = 10;
  EXPECT_THROW((void)decode_pgm(encode_pgm(random_image(4, 4, 1)), "limit.pgm", small), ParseError);
}

TEST(GrayImage, LyingPngSizeIsRejectedBeforeAllocating) {
  auto png = encode_png(random_image(8, 8, 9));
  // IHDR: length at 8, type at 12, width at 16, height at 20, CRC at 29.
  auto lie = png;
  patch_png_u32(lie, 16, 40000, 12, 13);
  patch_png_u32(lie, 20, 40000, 12, 13);
  try {
    (void)decode_png(lie, "lie.png");
    FAIL() << "no error";
  } catch (const ParseError& e) {
    EXPECT_EQ(e.location().field, "size");
    EXPECT_NE(e.problem().find("40000 x 40000"), std::string::npos) << e.problem();
  }
  auto wide = png;
  patch_png_u32(wide, 16, 70000, 12, 13);  // above the 65536 side limit
  EXPECT_THROW((void)decode_png(wide, "wide.png"), ParseError);
  auto tall = png;
  patch_png_u32(tall, 20, 9, 12, 13);  // one row more than the data holds
  EXPECT_THROW((void)decode_png(tall, "tall.png"), ParseError);
  auto crc = png;
  crc[30] ^= 0xFF;  // broken IHDR CRC
  EXPECT_THROW((void)decode_png(crc, "crc.png"), ParseError);
  EXPECT_THROW((void)decode_gray_image(bytes_of("GIF89a"), "x.gif"), ParseError);
}

// ---------------------------------------------------------------- yaml ---

TEST(RosMapYaml, ParsesMapServerFile) {
  const std::string text =
      "---\n# written by hand\nimage: \"my map.pgm\"   # quoted\nresolution: 0.025\n"
      "origin: [-12.5, 3.0, 0]\nnegate: true\noccupied_thresh: 0.7\nfree_thresh: 0.2\n"
      "mode: scale\nframe_id: map\n";
  const RosMapYaml y = parse_ros_map_yaml(text, "m.yaml");
  EXPECT_EQ(y.image, "my map.pgm");
  EXPECT_EQ(y.resolution, 0.025);
  EXPECT_EQ(y.origin, (std::array<double, 3>{-12.5, 3.0, 0.0}));
  EXPECT_TRUE(y.negate);
  EXPECT_EQ(y.occupied_thresh, 0.7);
  EXPECT_EQ(y.free_thresh, 0.2);
  EXPECT_EQ(y.mode, RosMapMode::Scale);
  EXPECT_EQ(y.unknown_keys, std::vector<std::string>{"frame_id"});
  // Format then parse gives the same values.
  const RosMapYaml again = parse_ros_map_yaml(format_ros_map_yaml(y), "again.yaml");
  EXPECT_EQ(again.image, y.image);
  EXPECT_EQ(again.resolution, y.resolution);
  EXPECT_EQ(again.origin, y.origin);
  EXPECT_EQ(again.negate, y.negate);
  EXPECT_EQ(again.mode, y.mode);
}

TEST(RosMapYaml, MapSaverLayout) {
  RosMapYaml y;
  y.image = "map.png";
  y.resolution = 0.05f;
  y.origin = {-10.05f, 3.5, 0};
  EXPECT_EQ(format_ros_map_yaml(y),
            "image: map.png\nresolution: 0.05\norigin: [-10.05, 3.5, 0.0]\nnegate: 0\n"
            "occupied_thresh: 0.65\nfree_thresh: 0.196\n");
}

// Quotes only open a quoted scalar where a scalar starts; inside double
// quotes \" is a quote, not the end; a tab before # starts a comment. A
// value of quotes, bytes above 127, a tab and a # formats and parses back
// unchanged (found by rove_grid_io_fuzz: the comment scan closed the quoted
// string at its first escaped quote).
TEST(RosMapYaml, QuotesCommentsAndEscapesRoundTrip) {
  const std::string base = "resolution: 0.05\norigin: [0, 0, 0]\n";
  EXPECT_EQ(parse_ros_map_yaml("image: map\"x.png # note\n" + base, "a.yaml").image, "map\"x.png");
  EXPECT_EQ(parse_ros_map_yaml("image: map.png\t# note\n" + base, "b.yaml").image, "map.png");
  EXPECT_EQ(parse_ros_map_yaml("image: \"a \\\" # b\" # c\n" + base, "c.yaml").image, "a \" # b");
  EXPECT_EQ(parse_ros_map_yaml("image: 'it''s # here'\n" + base, "d.yaml").image, "it's # here");
  EXPECT_EQ(parse_ros_map_yaml("image: a#b\n" + base, "e.yaml").image, "a#b");
  const std::string odd = std::string("map.\xff\xff\"\"\"\t#\x06\"1 '2' \\");
  RosMapYaml y;
  y.image = odd;
  y.resolution = 0.05;
  const RosMapYaml z = parse_ros_map_yaml(format_ros_map_yaml(y), "f.yaml");
  EXPECT_EQ(z.image, odd);
  // The fuzzer's input: a plain scalar with literal quotes, cut at "\t#".
  const std::string fuzz = std::string("image: map.\xff\xff\"\"\t#\x06\"\"1\n") + base;
  const RosMapYaml f = parse_ros_map_yaml(fuzz, "g.yaml");
  EXPECT_EQ(f.image, "map.\xff\xff\"\"");
  EXPECT_EQ(parse_ros_map_yaml(format_ros_map_yaml(f), "h.yaml").image, f.image);
}

TEST(RosMapYaml, ErrorsNameLineAndKey) {
  const auto error_of = [](const std::string& text) -> ParseError {
    try {
      (void)parse_ros_map_yaml(text, "bad.yaml");
    } catch (const ParseError& e) {
      return e;
    }
    ADD_FAILURE() << "no error for:\n" << text;
    return ParseError({}, "");
  };
  const std::string ok_head = "image: m.pgm\nresolution: 0.1\n";
  auto e = error_of(ok_head + "origin: [1, 2]\n");
  EXPECT_EQ(e.location().line, 3u);
  EXPECT_EQ(e.location().field, "origin");
  e = error_of(ok_head + "origin: [1, 2, 0]\nresolution: 0.2\n");
  EXPECT_EQ(e.location().line, 4u);
  EXPECT_NE(e.problem().find("duplicate"), std::string::npos);
  e = error_of("image: m.pgm\nresolution: abc\norigin: [0, 0, 0]\n");
  EXPECT_EQ(e.location().field, "resolution");
  e = error_of("image: m.pgm\nresolution: -1\norigin: [0, 0, 0]\n");
  EXPECT_EQ(e.location().field, "resolution");
  e = error_of("resolution: 1\norigin: [0, 0, 0]\n");
  EXPECT_EQ(e.location().field, "image");
  e = error_of(ok_head + "origin: [0, 0, 0]\nmode: fancy\n");
  EXPECT_EQ(e.location().field, "mode");
  e = error_of(ok_head + "origin: [0, 0, 0]\nnegate: 2\n");
  EXPECT_EQ(e.location().field, "negate");
  e = error_of(ok_head + "origin: [0, 0, 0]\nfree_thresh: 0.9\n");
  EXPECT_EQ(e.location().field, "free_thresh");
  e = error_of(ok_head + "origin:\n  x: 1\n");
  EXPECT_EQ(e.location().line, 3u);
  e = error_of(ok_head + "origin: [0, nan, 0]\n");
  EXPECT_EQ(e.location().field, "origin");
  e = error_of(ok_head + "origin: [0, 1e999, 0]\n");
  EXPECT_EQ(e.location().field, "origin");
  e = error_of(ok_head + "origin: [0, 0, 0\n");
  EXPECT_EQ(e.location().field, "origin");
  e = error_of("image: 'unterminated\n");
  EXPECT_EQ(e.location().line, 1u);
}

TEST(RosMapYaml, EveryTruncationIsAParseError) {
  // origin, required, comes last and ends with ']': every cut loses it.
  const std::string text =
      "image: map.pgm\nresolution: 0.05\nnegate: 0\noccupied_thresh: 0.65\n"
      "free_thresh: 0.196\norigin: [-1.5, 2.25, 0.0]";
  for (std::size_t n = 0; n < text.size(); ++n) {
    EXPECT_THROW((void)parse_ros_map_yaml(text.substr(0, n), "cut.yaml"), ParseError) << n;
  }
  EXPECT_NO_THROW((void)parse_ros_map_yaml(text, "whole.yaml"));
}

// ----------------------------------------------------------- grid+yaml ---

// A hand-written map_server map: 4 x 3 PGM (P2), known cells in each mode.
class HandWrittenRosMap : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = temp_dir("hand");
    write_text(dir_ / "tiny.pgm", "P2\n4 3\n255\n0 254 205 100\n255 128 50 10\n0 0 0 255\n");
  }
  RosMap load(const std::string& extra) {
    write_text(dir_ / "map.yaml",
               "image: tiny.pgm\nresolution: 0.5\norigin: [-1.0, 2.0, 0.0]\n"
               "occupied_thresh: 0.65\nfree_thresh: 0.196  # map_saver's\n" + extra);
    return load_ros_map((dir_ / "map.yaml").string());
  }
  // Expected free probability of image row v (0 = top), column u.
  static void expect_row(const OccupancyGrid& g, int v, std::array<float, 4> p_free) {
    const auto& lut = LogOddsLut<std::int8_t>::instance();
    for (int u = 0; u < 4; ++u) {
      EXPECT_EQ(g.cell(u, 2 - v), lut.p2l(p_free[static_cast<std::size_t>(u)]))
          << "pixel (" << u << ", " << v << ")";
    }
  }
  fs::path dir_;
};

TEST_F(HandWrittenRosMap, Trinary) {
  const RosMap m = load("negate: 0\n");
  const OccupancyGrid& g = m.grid;
  EXPECT_EQ(g.size_x(), 4u);
  EXPECT_EQ(g.size_y(), 3u);
  EXPECT_EQ(g.x_min(), -1.0f);
  EXPECT_EQ(g.y_min(), 2.0f);
  EXPECT_EQ(g.x_max(), 1.0f);
  EXPECT_EQ(g.y_max(), 3.5f);
  EXPECT_EQ(g.resolution(), 0.5f);
  EXPECT_EQ(m.image_path, (dir_ / "tiny.pgm").string());
  // occ = (255 − v)/255: 0 → 1 occupied, 254 → free, 205 → 0.19608 unknown,
  // 100 → 0.608 unknown, 255 free, 128 unknown, 50 → 0.804 occupied, 10 occupied.
  expect_row(g, 0, {0.0f, 1.0f, 0.5f, 0.5f});
  expect_row(g, 1, {1.0f, 0.5f, 0.0f, 0.0f});
  expect_row(g, 2, {0.0f, 0.0f, 0.0f, 1.0f});
  // The world point in the top-left pixel is occupied.
  EXPECT_EQ(g.free_probability_at(-0.9, 3.4), LogOddsLut<std::int8_t>::instance().l2p(g.cell(0, 2)));
}

TEST_F(HandWrittenRosMap, Negate) {
  const RosMap m = load("negate: 1\n");
  // occ = v/255: 0 free, 254 occupied, 205 → 0.804 occupied, 100 → 0.392
  // unknown, 255 occupied, 128 unknown, 50 → 0.19608 unknown, 10 free.
  expect_row(m.grid, 0, {1.0f, 0.0f, 0.0f, 0.5f});
  expect_row(m.grid, 1, {0.0f, 0.5f, 0.5f, 1.0f});
}

TEST_F(HandWrittenRosMap, Scale) {
  const RosMap m = load("negate: 0\nmode: scale\n");
  // 100: ratio (0.6078 − 0.196)/0.454 = 0.907 → 1 + 88.9 → 89 %;
  // 128: occ 0.4980, ratio 0.6653 → 66 %; 205: ratio 0.0002 → 1 %.
  const auto pct = [](int q) { return 1.0f - static_cast<float>(q) / 100.0f; };
  expect_row(m.grid, 0, {0.0f, 1.0f, pct(1), pct(89)});
  expect_row(m.grid, 1, {1.0f, pct(66), 0.0f, 0.0f});
}

TEST_F(HandWrittenRosMap, Raw) {
  const RosMap m = load("negate: 1\nmode: raw\n");  // negate does not apply to raw
  // v ≤ 100 is the occupancy in percent, above unknown.
  expect_row(m.grid, 0, {1.0f, 0.5f, 0.5f, 0.0f});
  expect_row(m.grid, 1, {0.5f, 0.5f, 0.5f, 0.9f});
}

TEST_F(HandWrittenRosMap, UnknownKeysAreReportedAndYawRejected) {
  const RosMap m = load("negate: 0\nframe_id: map\nsomething: [1, 2]\n");
  EXPECT_EQ(m.yaml.unknown_keys, (std::vector<std::string>{"frame_id", "something"}));
  write_text(dir_ / "yaw.yaml", "image: tiny.pgm\nresolution: 0.5\norigin: [0, 0, 0.3]\n");
  try {
    (void)load_ros_map((dir_ / "yaw.yaml").string());
    FAIL() << "no error";
  } catch (const ParseError& e) {
    EXPECT_EQ(e.location().field, "origin");
    EXPECT_NE(std::string(e.what()).find("yaw.yaml"), std::string::npos);
  }
  write_text(dir_ / "missing.yaml", "image: nothere.png\nresolution: 0.5\norigin: [0, 0, 0]\n");
  EXPECT_THROW((void)load_ros_map((dir_ / "missing.yaml").string()), IoError);
}

TEST(GridImage, TrinaryPngAndPgmRoundTripKeepClassesAndGeometry) {
  const OccupancyGrid g = random_grid(11);
  const fs::path dir = temp_dir("trinary");
  for (ImageFormat f : {ImageFormat::Png, ImageFormat::Pgm}) {
    GridImageOptions o;
    o.format = f;
    const RosMapFiles files = save_ros_map((dir / "map").string(), g, o);
    EXPECT_EQ(files.image, (dir / (f == ImageFormat::Png ? "map.png" : "map.pgm")).string());
    const RosMap m = load_ros_map(files.yaml);
    const OccupancyGrid& h = m.grid;
    ASSERT_EQ(h.size_x(), g.size_x());
    ASSERT_EQ(h.size_y(), g.size_y());
    EXPECT_EQ(h.x_min(), g.x_min());
    EXPECT_EQ(h.y_min(), g.y_min());
    EXPECT_EQ(h.resolution(), g.resolution());
    EXPECT_FLOAT_EQ(h.x_max(), g.x_max());
    EXPECT_FLOAT_EQ(h.y_max(), g.y_max());
    std::size_t counts[3] = {};
    for (int cy = 0; cy < static_cast<int>(g.size_y()); ++cy) {
      for (int cx = 0; cx < static_cast<int>(g.size_x()); ++cx) {
        const Cls a = class_of(g.free_probability(cx, cy));
        ASSERT_EQ(a, class_of(h.free_probability(cx, cy))) << cx << ", " << cy;
        ++counts[static_cast<int>(a)];
      }
    }
    EXPECT_GT(counts[0], 100u);
    EXPECT_GT(counts[1], 100u);
    EXPECT_GT(counts[2], 100u);
  }
}

TEST(GridImage, ProbabilityImageIsRoundedFreeProbability) {
  const OccupancyGrid g = random_grid(12);
  GridImageOptions o;
  o.mode = RosMapMode::Scale;
  const GrayImage img = grid_to_image(g, o);
  for (std::uint32_t cy = 0; cy < g.size_y(); ++cy) {
    for (std::uint32_t cx = 0; cx < g.size_x(); ++cx) {
      const float p = g.free_probability(static_cast<int>(cx), static_cast<int>(cy));
      ASSERT_EQ(img.at(cx, g.size_y() - 1 - cy), std::lround(255.0f * p));
    }
  }
  // Read back with map_server's trinary rule: the class of each pixel.
  RosMapYaml y;
  y.resolution = g.resolution();
  y.origin = {g.x_min(), g.y_min(), 0};
  const OccupancyGrid h = grid_from_image(img, y);
  for (std::uint32_t cy = 0; cy < g.size_y(); ++cy) {
    for (std::uint32_t cx = 0; cx < g.size_x(); ++cx) {
      const double occ = (255.0 - img.at(cx, g.size_y() - 1 - cy)) / 255.0;
      const Cls want = occ > 0.65 ? Cls::Occupied : occ < 0.196 ? Cls::Free : Cls::Unknown;
      ASSERT_EQ(class_of(h.free_probability(static_cast<int>(cx), static_cast<int>(cy))), want);
    }
  }
}

// Regression: icp-slam wrote 255·p(free) images with a yaml that did not
// say so (map_server read them as trinary); the one grid writer now states
// its mode, and map_server's scale rule reads the image back.
TEST(GridImage, ScaleModeImageSaysModeScaleInItsYaml) {
  const OccupancyGrid g = random_grid(21);
  const fs::path dir = temp_dir("scale");
  GridImageOptions o;
  o.mode = RosMapMode::Scale;
  const RosMapFiles files = save_ros_map((dir / "map").string(), g, o);
  std::ifstream in(files.yaml);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("mode: scale\n"), std::string::npos) << text;
  const RosMap m = load_ros_map(files.yaml);
  EXPECT_EQ(m.yaml.mode, RosMapMode::Scale);
  const GrayImage img = grid_to_image(g, o);
  std::size_t between = 0;
  for (std::uint32_t cy = 0; cy < g.size_y(); ++cy) {
    for (std::uint32_t cx = 0; cx < g.size_x(); ++cx) {
      const double occ = (255.0 - img.at(cx, g.size_y() - 1 - cy)) / 255.0;
      const float back = m.grid.free_probability(static_cast<int>(cx), static_cast<int>(cy));
      if (occ > 0.65) {
        ASSERT_EQ(class_of(back), Cls::Occupied);
      } else if (occ < 0.196) {
        ASSERT_EQ(class_of(back), Cls::Free);
      } else {
        // map_server: an occupancy of 1 + 98·ratio percent.
        const double percent = std::floor(1 + 98 * (occ - 0.196) / (0.65 - 0.196));
        ASSERT_NEAR(back, 1.0 - percent / 100.0, 0.02) << cx << ", " << cy;  // int8 log-odds
        ++between;
      }
    }
  }
  EXPECT_GT(between, 100u);
}

TEST(GridImage, RawModeIsNotWritten) {
  GridImageOptions o;
  o.mode = RosMapMode::Raw;
  EXPECT_THROW(grid_to_image(random_grid(22), o), InvalidArgument);
}

// The one PNG encoder also writes palette images (icp-slam's point picture).
TEST(GrayImage, PalettePngDecodesToTheChannelAverage) {
  GrayImage img{5, 3, std::vector<std::uint8_t>(15)};
  for (std::size_t i = 0; i < img.pixels.size(); ++i) img.pixels[i] = static_cast<std::uint8_t>(i % 3);
  PngEncoding e;
  e.palette = {{255, 255, 255}, {40, 40, 40}, {220, 30, 30}};
  for (bool fast : {false, true}) {
    e.fast = fast;
    const GrayImage back = decode_png(encode_png(img, e), "palette");
    ASSERT_EQ(back.width, 5u);
    ASSERT_EQ(back.height, 3u);
    for (std::size_t i = 0; i < img.pixels.size(); ++i) {
      const PaletteColor& c = e.palette[img.pixels[i]];
      ASSERT_EQ(back.pixels[i], (c.r + c.g + c.b) / 3) << i;
    }
  }
  img.pixels[7] = 3;  // not an index into the palette
  EXPECT_THROW(encode_png(img, e), InvalidArgument);
}

// Regression: reading /dev/zero as a map image or a map.yaml grew without
// bound; devices, FIFOs and directories are refused by name.
TEST(GrayImage, DevZeroAsMapImageOrYamlIsRefused) {
  for (const char* dev : {"/dev/zero", "/dev/urandom"}) {
    try {
      (void)read_gray_image(dev);
      ADD_FAILURE() << dev;
    } catch (const IoError& e) {
      EXPECT_NE(std::string(e.what()).find(dev), std::string::npos) << e.what();
    }
    EXPECT_THROW((void)read_ros_map_yaml(dev), IoError);
  }
  EXPECT_THROW((void)read_gray_image(fs::temp_directory_path().string()), IoError);
}

TEST(GridImage, UnusualThresholdsStillReadBackUnknown) {
  // With free_thresh 0.5, map_saver's 205 (occupancy 0.196) would read as
  // free; the writer takes the gray in the middle of the thresholds instead.
  OccupancyGrid g(0, 1, 0, 1, 0.5f);  // all unknown
  GridImageOptions o;
  o.occupied_thresh = 0.9;
  o.free_thresh = 0.5;
  EXPECT_EQ(grid_to_image(g, o).pixels[0], 77);  // 255·(1 − 0.7), rounded
  const RosMapFiles f = save_ros_map((temp_dir("thresh") / "m").string(), g, o);
  const RosMap m = load_ros_map(f.yaml);
  EXPECT_EQ(m.yaml.free_thresh, 0.5);
  for (auto c : m.grid.cells()) EXPECT_EQ(c, 0);
}

// The MRPT Malaga campus map saved as PNG + yaml and read back: every cell
// in the same class.
TEST(GridImage, MrptGridmapThroughPngAndYaml) {
  const std::string path = test_data::mrpt_package_file("2006-MalagaCampus.gridmap.gz");
  ASSERT_TRUE(fs::exists(path)) << "missing " << path << " (Debian mrpt-common, see scripts/install-deps)";
  const OccupancyGrid g = load_mrpt_gridmap(path).grid;
  const RosMapFiles f = save_ros_map((temp_dir("malaga") / "malaga").string(), g);
  const OccupancyGrid h = load_ros_map(f.yaml).grid;
  ASSERT_EQ(h.size_x(), g.size_x());
  ASSERT_EQ(h.size_y(), g.size_y());
  EXPECT_EQ(h.x_min(), g.x_min());
  EXPECT_EQ(h.y_min(), g.y_min());
  EXPECT_EQ(h.resolution(), g.resolution());
  std::size_t differ = 0, occupied = 0, free = 0;
  for (int cy = 0; cy < static_cast<int>(g.size_y()); ++cy) {
    for (int cx = 0; cx < static_cast<int>(g.size_x()); ++cx) {
      const Cls a = class_of(g.free_probability(cx, cy));
      differ += a != class_of(h.free_probability(cx, cy));
      occupied += a == Cls::Occupied;
      free += a == Cls::Free;
    }
  }
  EXPECT_EQ(differ, 0u);
  EXPECT_GT(occupied, 1000u);
  EXPECT_GT(free, 10000u);
}

// -------------------------------------------------------------- binary ---

TEST(GridBinary, RoundTripIsExact) {
  const OccupancyGrid g = random_grid(13);
  const fs::path dir = temp_dir("binary");
  for (auto c : {FileCompression::None, FileCompression::Gzip}) {
    const std::string p = (dir / "g.rovegrid").string();
    save_grid(p, g, c);
    const OccupancyGrid h = load_grid(p);
    EXPECT_TRUE(h == g);
    EXPECT_FALSE(h.empty());
  }
  OccupancyGrid16 g16(-1, 1, -2, 2, 0.1f);
  g16.set_cell(3, 4, -12345);
  MemoryOutStream out;
  OutArchive oa(out);
  save(oa, g16);
  MemoryInStream in(out.data());
  InArchive ia(in);
  OccupancyGrid16 h16;
  load(ia, h16);
  EXPECT_TRUE(h16 == g16);
  EXPECT_TRUE(h16.empty());
  // 16-bit cells do not load into an 8-bit grid.
  MemoryInStream in2(out.data());
  InArchive ia2(in2);
  OccupancyGrid h8;
  EXPECT_THROW(load(ia2, h8), ParseError);
}

OccupancyGrid frozen_grid() {
  OccupancyGrid g(-1.0f, 1.0f, 0.5f, 2.0f, 0.5f);  // 4 x 3
  for (int i = 0; i < 12; ++i) g.set_cell(i % 4, i / 4, static_cast<std::int8_t>(i * 21 - 120));
  g.set_empty(false);
  return g;
}

// Version 1 is frozen: the file in tests/data must keep loading to these
// values, and writing the same grid must give the same bytes.
TEST(GridBinary, FrozenVersion1File) {
  const std::string path = kData + "grid_v1.rovegrid";
  const OccupancyGrid g = load_grid(path);
  EXPECT_EQ(g.size_x(), 4u);
  EXPECT_EQ(g.size_y(), 3u);
  EXPECT_EQ(g.x_min(), -1.0f);
  EXPECT_EQ(g.x_max(), 1.0f);
  EXPECT_EQ(g.y_min(), 0.5f);
  EXPECT_EQ(g.y_max(), 2.0f);
  EXPECT_EQ(g.resolution(), 0.5f);
  for (int i = 0; i < 12; ++i) EXPECT_EQ(g.cell(i % 4, i / 4), i * 21 - 120);
  EXPECT_FALSE(g.empty());
  const std::string again = (temp_dir("frozen") / "again.rovegrid").string();
  save_grid(again, frozen_grid());
  EXPECT_EQ(read_file_bytes(again), read_file_bytes(path));
}

TEST(GridBinary, EveryTruncationIsAParseError) {
  const auto bytes = read_file_bytes(kData + "grid_v1.rovegrid");
  const fs::path dir = temp_dir("cut");
  for (std::size_t n = 0; n < bytes.size(); ++n) {
    const std::string p = (dir / "cut.rovegrid").string();
    write_file_bytes(p, {bytes.data(), n});
    EXPECT_THROW((void)load_grid(p), ParseError) << "prefix " << n;
  }
  // A lying cell count.
  auto lie = bytes;
  lie[8 + 2 + 20] = 0xFF;  // size_x low byte
  const std::string p = (dir / "lie.rovegrid").string();
  write_file_bytes(p, lie);
  EXPECT_THROW((void)load_grid(p), ParseError);
}

}  // namespace
}  // namespace rove
