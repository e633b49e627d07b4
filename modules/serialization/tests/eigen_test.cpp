#include "rove/serialization/eigen.h"

#include <gtest/gtest.h>

#include "rove/core/error.h"
#include "rove/serialization/stl.h"
#include "test_util.h"

namespace rove {
namespace {

using test::bytes_of;
using test::from_hex;
using test::load_from;
using test::round_trip;
using test::to_hex;

TEST(Eigen, FixedAndDynamicMatricesRoundTrip) {
  const Eigen::Matrix3d a = Eigen::Matrix3d::Random();
  EXPECT_EQ(round_trip(a), a);
  const Eigen::Matrix<float, 2, 5> b = Eigen::Matrix<float, 2, 5>::Random();
  EXPECT_EQ(round_trip(b), b);
  const Eigen::MatrixXd c = Eigen::MatrixXd::Random(4, 7);
  EXPECT_EQ(round_trip(c), c);
  const Eigen::VectorXf d = Eigen::VectorXf::Random(9);
  EXPECT_EQ(round_trip(d), d);
  const Eigen::RowVector3d e(1, 2, 3);
  EXPECT_EQ(round_trip(e), e);
  const Eigen::Matrix<std::int32_t, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> f =
      Eigen::Matrix<std::int32_t, 3, 2>::Random();
  EXPECT_EQ(round_trip(f), f);
  const Eigen::MatrixXd empty(0, 3);
  const Eigen::MatrixXd empty_back = round_trip(empty);
  EXPECT_EQ(empty_back.rows(), 0);
  EXPECT_EQ(empty_back.cols(), 3);
  const std::vector<Eigen::Vector2d> vv{{1, 2}, {3, 4}};
  EXPECT_EQ(round_trip(vv), vv);
}

// rows, cols, then column-major data, whatever the storage order.
TEST(Eigen, FrozenLayoutIsColumnMajor) {
  Eigen::Matrix<std::uint8_t, 2, 3> m;
  m << 1, 2, 3, 4, 5, 6;
  const std::string expected = "02 00 00 00 03 00 00 00 01 04 02 05 03 06";
  EXPECT_EQ(to_hex(bytes_of(m)), expected);
  const Eigen::Matrix<std::uint8_t, 2, 3, Eigen::RowMajor> r = m;
  EXPECT_EQ(to_hex(bytes_of(r)), expected);
  using Dyn = Eigen::Matrix<std::uint8_t, Eigen::Dynamic, Eigen::Dynamic>;
  const Dyn back = load_from<Dyn>(from_hex(expected));
  EXPECT_EQ(back, m);
  Eigen::Vector2d v(1.0, -2.0);
  EXPECT_EQ(to_hex(bytes_of(v)),
            "02 00 00 00 01 00 00 00 00 00 00 00 00 00 f0 3f 00 00 00 00 00 00 00 c0");
}

TEST(Eigen, StoredSizeMustFitAFixedType) {
  const auto bytes = bytes_of(Eigen::Matrix2d::Identity().eval());
  MemoryInStream in(std::span<const std::byte>(bytes), "m.bin");
  InArchive ar(in);
  Eigen::Matrix3d m;
  try {
    ar >> m;
    FAIL() << "expected ParseError";
  } catch (const ParseError& e) {
    EXPECT_EQ(e.location().offset, 0u);
    EXPECT_EQ(e.location().field, "matrix");
  }
  Eigen::Matrix<double, Eigen::Dynamic, 1, 0, 3, 1> bounded;
  EXPECT_THROW(load_from<decltype(bounded)>(bytes_of(Eigen::VectorXd::Zero(4).eval())),
               ParseError);
}

TEST(Eigen, HugeDimensionsAreRejectedBeforeAllocating) {
  // 65535 x 65535 doubles declared, 8 bytes present.
  const auto bytes = from_hex("ff ff 00 00 ff ff 00 00 00 00 00 00 00 00 f0 3f");
  MemoryInStream in{std::span<const std::byte>(bytes)};
  InArchive ar(in, ArchiveLimits{.max_length = ~std::uint64_t{0}});
  Eigen::MatrixXd m;
  EXPECT_THROW(ar >> m, ParseError);
  MemoryInStream in2{std::span<const std::byte>(bytes)};
  InArchive capped(in2);  // default cap 2^28 < 65535^2
  EXPECT_THROW(capped >> m, ParseError);
}

TEST(Eigen, EveryTruncationIsAParseError) {
  const Eigen::MatrixXd value = Eigen::MatrixXd::Random(2, 3);
  const auto bytes = bytes_of(value);
  for (std::size_t k = 0; k < bytes.size(); ++k) {
    MemoryInStream in(std::span<const std::byte>(bytes.data(), k));
    InArchive ar(in);
    Eigen::MatrixXd back;
    EXPECT_THROW(ar >> back, ParseError) << k;
  }
}

}  // namespace
}  // namespace rove

namespace rove {
namespace {

// Fuzzer finding: a 0 x 2^32-1 matrix has no coefficient, but assigning it
// looped over the empty dimension. Such a dimension is now checked against
// the cap, and empty matrices are sized without touching coefficients.
TEST(Eigen, RegressionEmptyMatrixWithHugeDimension) {
  using test::from_hex;
  EXPECT_THROW(load_from<Eigen::MatrixXd>(from_hex("00 00 00 00 ff ff ff ff")), ParseError);
  const auto m = load_from<Eigen::MatrixXd>(from_hex("00 00 00 00 2c 01 00 00"));
  EXPECT_EQ(m.rows(), 0);
  EXPECT_EQ(m.cols(), 300);
}

}  // namespace
}  // namespace rove
