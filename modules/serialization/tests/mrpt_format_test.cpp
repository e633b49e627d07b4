#include "rove/serialization/mrpt_format.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <numbers>
#include <variant>

#include "rove/core/error.h"
#include "rove/serialization/input_file.h"
#include "rove/serialization/mrpt_class_readers.h"
#include "test_util.h"

namespace rove {
namespace {

using test::from_hex;

MrptObjectHeader header_of(const std::vector<std::byte>& bytes, std::uint64_t* end = nullptr) {
  MemoryInStream in(std::span<const std::byte>(bytes), "mrpt.bin");
  InArchive ar(in);
  MrptObjectHeader h = read_mrpt_object_header(ar);
  if (end != nullptr) *end = ar.offset();
  return h;
}

ParseError header_error(const std::vector<std::byte>& bytes) {
  MemoryInStream in(std::span<const std::byte>(bytes), "mrpt.bin");
  InArchive ar(in);
  try {
    (void)read_mrpt_object_header(ar);
  } catch (const ParseError& e) {
    return e;
  }
  ADD_FAILURE() << "header was accepted";
  return ParseError({}, "");
}

TEST(MrptFormat, CurrentHeader) {
  std::uint64_t end = 0;
  // 0x80 | 7, "CPose2D", version 1.
  const auto h = header_of(from_hex("87 43 50 6f 73 65 32 44 01 ff"), &end);
  EXPECT_EQ(h.class_name, "CPose2D");
  EXPECT_EQ(h.version, 1);
  EXPECT_EQ(h.offset, 0u);
  EXPECT_FALSE(h.is_null);
  EXPECT_FALSE(h.old_format);
  EXPECT_EQ(end, 9u);
}

TEST(MrptFormat, NullObjectHasNoVersion) {
  std::uint64_t end = 0;
  const auto bytes = from_hex("87 6e 75 6c 6c 70 74 72 88");
  const auto h = header_of(bytes, &end);
  EXPECT_TRUE(h.is_null);
  EXPECT_EQ(h.class_name, "nullptr");
  EXPECT_EQ(end, 8u);

  MrptClassReaders<int> readers;
  MemoryInStream in{std::span<const std::byte>(bytes)};
  InArchive ar(in);
  EXPECT_EQ(readers.read_object(ar), 0);
  EXPECT_TRUE(ar.at_end());
}

TEST(MrptFormat, OldFramingBeforeMrpt055) {
  // u32 name length 7, "CPose2D", i32 version 2, a one-byte payload, no end marker.
  const auto bytes = from_hex("07 00 00 00 43 50 6f 73 65 32 44 02 00 00 00 2a");
  std::uint64_t end = 0;
  const auto h = header_of(bytes, &end);
  EXPECT_TRUE(h.old_format);
  EXPECT_EQ(h.class_name, "CPose2D");
  EXPECT_EQ(h.version, 2);
  EXPECT_EQ(end, 15u);

  MrptClassReaders<int> readers;
  readers.add("CPose2D", [](InArchive& ar, const MrptObjectHeader& hd) {
    EXPECT_EQ(hd.version, 2);
    return static_cast<int>(ar.read_scalar<std::uint8_t>());
  });
  MemoryInStream in{std::span<const std::byte>(bytes)};
  InArchive ar(in);
  EXPECT_EQ(readers.read_object(ar), 42);
  EXPECT_TRUE(ar.at_end());
}

TEST(MrptFormat, MalformedHeadersNameTheOffset) {
  // Old framing whose length has high bytes set (e.g. gzip data read raw).
  auto e = header_error(from_hex("1f 8b 08 00 00 00"));
  EXPECT_EQ(e.location().offset, 0u);
  // Class name longer than MRPT accepts (121).
  e = header_error(from_hex("f9 41 41 41"));
  EXPECT_EQ(e.location().offset, 0u);
  EXPECT_NE(e.problem().find("121"), std::string::npos);
  // Old-style version out of range.
  e = header_error(from_hex("01 00 00 00 41 ff 00 00 00"));
  EXPECT_EQ(e.location().offset, 5u);
  EXPECT_EQ(e.location().field, "A");
  // Truncated name.
  e = header_error(from_hex("87 43 50 6f"));
  EXPECT_EQ(e.location().offset, 1u);
  // Missing version byte.
  e = header_error(from_hex("81 41"));
  EXPECT_EQ(e.location().offset, 2u);
  EXPECT_EQ(e.location().field, "A");
  // Nothing at all.
  e = header_error({});
  EXPECT_EQ(e.location().offset, 0u);
}

TEST(MrptFormat, EndMarkerIsChecked) {
  const auto bytes = from_hex("81 41 00 07 88 81 41 00 07 89");
  MemoryInStream in(std::span<const std::byte>(bytes), "m.bin");
  InArchive ar(in);
  MrptClassReaders<int> readers;
  readers.add("A", [](InArchive& a, const MrptObjectHeader&) {
    return static_cast<int>(a.read_scalar<std::uint8_t>());
  });
  EXPECT_EQ(readers.read_object(ar), 7);
  try {
    (void)readers.read_object(ar);
    FAIL() << "expected ParseError";
  } catch (const ParseError& e) {
    EXPECT_EQ(e.location().offset, 9u);
    EXPECT_EQ(e.location().field, "A");
  }
}

TEST(MrptFormat, UnknownClassNamesClassAndOffset) {
  const auto bytes = from_hex("81 41 00 07 88 82 42 43 03 00 88");
  MemoryInStream in(std::span<const std::byte>(bytes), "m.bin");
  InArchive ar(in);
  MrptClassReaders<int> readers;
  readers.add("A", [](InArchive& a, const MrptObjectHeader&) {
    return static_cast<int>(a.read_scalar<std::uint8_t>());
  });
  EXPECT_TRUE(readers.contains("A"));
  EXPECT_FALSE(readers.contains("BC"));
  EXPECT_THROW(readers.add("A", [](InArchive&, const MrptObjectHeader&) { return 0; }),
               InvalidArgument);
  (void)readers.read_object(ar);
  try {
    (void)readers.read_object(ar);
    FAIL() << "expected ParseError";
  } catch (const ParseError& e) {
    EXPECT_EQ(e.location().offset, 5u);
    EXPECT_EQ(e.location().field, "BC");
    EXPECT_NE(e.problem().find("'BC'"), std::string::npos);
  }
}

TEST(MrptFormat, UnknownVersionHelperNamesClassVersionOffset) {
  const auto bytes = from_hex("00 81 41 05");
  MemoryInStream in{std::span<const std::byte>(bytes)};
  InArchive ar(in);
  (void)ar.read_scalar<std::uint8_t>();
  MrptClassReaders<int> readers;
  readers.add("A", [](InArchive& a, const MrptObjectHeader& h) -> int {
    throw_unknown_mrpt_version(a, h);
  });
  try {
    (void)readers.read_object(ar);
    FAIL() << "expected ParseError";
  } catch (const ParseError& e) {
    EXPECT_EQ(e.location().offset, 1u);
    EXPECT_EQ(e.location().field, "A");
    EXPECT_NE(e.problem().find("version 5"), std::string::npos);
  }
}

TEST(MrptFormat, Primitives) {
  const auto bytes = from_hex(
      "02 00 00 00 68 69 "                         // string "hi"
      "02 00 00 00 00 00 80 3f 00 00 00 c0 "       // vector<float> {1, -2}
      "03 00 00 00 01 00 05 "                      // vector<bool> {1, 0, 1}
      "02 00 00 00 01 00 00 00 61 00 00 00 00 "    // vector<string> {"a", ""}
      "02 00 00 00 02 00 00 00 "                   // 2x2 matrix, row-major
      "00 00 00 00 00 00 f0 3f 00 00 00 00 00 00 00 40 "
      "00 00 00 00 00 00 08 40 00 00 00 00 00 00 10 40 "
      "0b 00 00 00 73 74 64 3a 3a 76 65 63 74 6f 72 "  // "std::vector"
      "06 00 00 00 64 6f 75 62 6c 65 "                 // "double"
      "01 00 00 00 "                                   // count
      "07");                                           // lenient bool
  MemoryInStream in{std::span<const std::byte>(bytes)};
  InArchive ar(in);
  EXPECT_EQ(read_mrpt_string(ar, "s"), "hi");
  EXPECT_EQ(read_mrpt_vector<float>(ar, "v"), (std::vector<float>{1.f, -2.f}));
  EXPECT_EQ(read_mrpt_bool_vector(ar, "b"), (std::vector<bool>{true, false, true}));
  EXPECT_EQ(read_mrpt_string_vector(ar, "sv"), (std::vector<std::string>{"a", ""}));
  Eigen::MatrixXd m = read_mrpt_matrix<double>(ar, "m");
  Eigen::Matrix2d expected;
  expected << 1, 2, 3, 4;
  EXPECT_EQ(m, expected);
  const auto at = ar.offset();
  MemoryInStream again{std::span<const std::byte>(bytes)};
  InArchive ar2(again);
  std::vector<std::byte> skip(at);
  ar2.read_bytes(skip);
  EXPECT_THROW((void)read_mrpt_container_preamble(ar2, "std::deque", {"double"}, "c"), ParseError);
  EXPECT_EQ(read_mrpt_container_preamble(ar, "std::vector", {"double"}, "c"), 1u);
  EXPECT_TRUE(read_mrpt_bool(ar, "flag"));
  EXPECT_TRUE(ar.at_end());
}

TEST(MrptFormat, HugeMrptLengthsAreRejectedBeforeAllocating) {
  const auto bytes = from_hex("ff ff ff 7f 00 00 80 3f");
  MemoryInStream in{std::span<const std::byte>(bytes)};
  InArchive ar(in, ArchiveLimits{.max_length = ~std::uint64_t{0}});
  EXPECT_THROW((void)read_mrpt_vector<float>(ar, "ranges"), ParseError);
  const auto mat = from_hex("ff ff 00 00 ff ff 00 00 00 00 80 3f");
  MemoryInStream in2{std::span<const std::byte>(mat)};
  InArchive ar2(in2, ArchiveLimits{.max_length = ~std::uint64_t{0}});
  EXPECT_THROW((void)read_mrpt_matrix<float>(ar2, "m"), ParseError);
}

// MRPT's demo dataset (gzip, rawlog format #1). MRPT reads it as: a
// CSensoryFrame version 2 holding one CObservation2DRangeScan version 6, whose
// sensor pose is a CPose3D version 1 that stores a CMatrixD (version 0, 4x4).
TEST(MrptFormat, RealRawlogFirstObjects) {
  const std::string path =
      std::string(ROVE_SOURCE_DIR) + "/data/mrpt/2006-01ENE-21-SENA_Telecom_Faculty_one_loop_only.rawlog";
  ASSERT_TRUE(std::filesystem::exists(path)) << "missing test data: " << path;
  auto in = open_input_file(path);
  InArchive ar(*in);

  const MrptObjectHeader frame = read_mrpt_object_header(ar);
  EXPECT_EQ(frame.class_name, "CSensoryFrame");
  EXPECT_EQ(frame.version, 2);
  EXPECT_EQ(frame.offset, 0u);
  EXPECT_FALSE(frame.old_format);
  EXPECT_EQ(ar.read_scalar<std::uint32_t>("observation count"), 1u);

  const MrptObjectHeader scan = read_mrpt_object_header(ar);
  EXPECT_EQ(scan.class_name, "CObservation2DRangeScan");
  EXPECT_EQ(scan.version, 6);
  EXPECT_EQ(scan.offset, 19u);
  EXPECT_EQ(ar.read_scalar<float>("aperture"), std::numbers::pi_v<float>);
  EXPECT_TRUE(read_mrpt_bool(ar, "rightToLeft"));
  EXPECT_EQ(ar.read_scalar<float>("maxRange"), 80.0f);

  using Value = std::variant<std::monostate, Eigen::MatrixXd>;
  MrptClassReaders<Value> readers;
  readers.add("CMatrixD", [](InArchive& a, const MrptObjectHeader& h) -> Value {
    if (h.version != 0) throw_unknown_mrpt_version(a, h);
    return read_mrpt_matrix<double>(a, "CMatrixD");
  });
  readers.add("CPose3D", [&readers](InArchive& a, const MrptObjectHeader& h) -> Value {
    if (h.version != 1) throw_unknown_mrpt_version(a, h);
    return readers.read_object(a);  // the homogeneous matrix
  });
  const Value pose = readers.read_object(ar);
  ASSERT_TRUE(std::holds_alternative<Eigen::MatrixXd>(pose));
  const auto& T = std::get<Eigen::MatrixXd>(pose);
  ASSERT_EQ(T.rows(), 4);
  ASSERT_EQ(T.cols(), 4);
  EXPECT_TRUE((T.topLeftCorner<3, 3>().isIdentity(0.0)));
  EXPECT_EQ(T(0, 3), static_cast<double>(0.78f));
  EXPECT_EQ(T(1, 3), 0.0);
  EXPECT_EQ(T(2, 3), static_cast<double>(0.3f));
  EXPECT_EQ(T.row(3), Eigen::RowVector4d(0, 0, 0, 1));
  EXPECT_EQ(ar.offset(), 210u);
  EXPECT_EQ(read_mrpt_vector<float>(ar, "scan").size(), 361u);
}

}  // namespace
}  // namespace rove

namespace rove {
namespace {

// Fuzzer finding (see Eigen.RegressionEmptyMatrixWithHugeDimension).
TEST(MrptFormat, RegressionEmptyMatrixWithHugeDimension) {
  const auto huge = from_hex("00 00 00 00 ff ff ff ff");
  MemoryInStream in{std::span<const std::byte>(huge)};
  InArchive ar(in);
  EXPECT_THROW((void)read_mrpt_matrix<double>(ar, "m"), ParseError);
  const auto small = from_hex("2c 01 00 00 00 00 00 00");
  MemoryInStream in2{std::span<const std::byte>(small)};
  InArchive ar2(in2);
  const auto m = read_mrpt_matrix<double>(ar2, "m");
  EXPECT_EQ(m.rows(), 300);
  EXPECT_EQ(m.cols(), 0);
}

}  // namespace
}  // namespace rove
