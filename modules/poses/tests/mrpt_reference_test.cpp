// Agreement with MRPT 2.5.8, case by case, on frozen reference results.
//
// data/reference/mrpt-2.5.8-poses.bin holds MRPT's outputs for the inputs
// that reference_cases.h regenerates (format and regeneration command in
// data/reference/README.md). Each test below recomputes one section with
// rove and compares:
//   - positions and other values: |rove − mrpt| ≤ 1e-9 · max(1, |mrpt|);
//   - angles: the wrapped difference ≤ 1e-9 rad;
//   - quaternions: up to sign where MRPT's sign is not canonical;
//   - covariances: max |Δ| ≤ 1e-9 · ‖C_mrpt‖_F.
// Every test prints the worst error of its section, the case and the
// component where it occurs.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <map>
#include <numbers>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "reference_cases.h"
#include "rove/poses/angle.h"
#include "rove/poses/euler.h"
#include "rove/poses/pdf_gaussian2.h"
#include "rove/poses/pdf_gaussian3.h"
#include "rove/poses/pdf_gaussian3_quat.h"
#include "rove/poses/point2.h"
#include "rove/poses/point3.h"
#include "rove/poses/pose2.h"
#include "rove/poses/pose3.h"
#include "rove/poses/pose3_quat.h"

namespace rove {
namespace {

namespace ref = rove::reference;

constexpr const char* kReferencePath = ROVE_SOURCE_DIR "/data/reference/mrpt-2.5.8-poses.bin";
constexpr char kMagic[8] = {'R', 'O', 'V', 'E', 'R', 'E', 'F', '\n'};
constexpr std::uint32_t kFormatVersion = 1;

/// Tolerance of every comparison (see the file comment for the measures).
constexpr double kTolerance = 1e-9;

// ---------------------------------------------------------------------------
// Reading the reference file

struct Section {
  std::string name;
  std::uint64_t cases = 0;
  std::uint32_t doubles_per_case = 0;
  std::vector<double> values;

  const double* row(std::size_t i) const { return values.data() + i * doubles_per_case; }
};

struct ReferenceFile {
  std::string error;  // empty when loaded
  std::string producer;
  std::map<std::string, Section, std::less<>> sections;
};

class ByteReader {
 public:
  explicit ByteReader(const std::vector<unsigned char>& bytes) : bytes_(bytes) {}

  bool u32(std::uint32_t& v) {
    if (!have(4)) return false;
    v = 0;
    for (int i = 0; i < 4; ++i) v |= std::uint32_t{bytes_[pos_ + i]} << (8 * i);
    pos_ += 4;
    return true;
  }
  bool u64(std::uint64_t& v) {
    if (!have(8)) return false;
    v = 0;
    for (int i = 0; i < 8; ++i) v |= std::uint64_t{bytes_[pos_ + i]} << (8 * i);
    pos_ += 8;
    return true;
  }
  bool f64(double& d) {
    std::uint64_t bits = 0;
    if (!u64(bits)) return false;
    std::memcpy(&d, &bits, sizeof d);
    return true;
  }
  bool str(std::string& s) {
    std::uint32_t n = 0;
    if (!u32(n) || !have(n)) return false;
    s.assign(reinterpret_cast<const char*>(bytes_.data() + pos_), n);
    pos_ += n;
    return true;
  }
  bool have(std::uint64_t n) const { return n <= bytes_.size() - pos_; }
  std::size_t offset() const { return pos_; }
  void skip(std::size_t n) { pos_ += n; }

 private:
  const std::vector<unsigned char>& bytes_;
  std::size_t pos_ = 0;
};

ReferenceFile load_reference() {
  ReferenceFile file;
  std::ifstream in(kReferencePath, std::ios::binary);
  if (!in) {
    file.error = std::string("cannot open the MRPT reference file ") + kReferencePath +
                 " (regenerate it with tools/mrpt_reference, see data/reference/README.md)";
    return file;
  }
  const std::vector<unsigned char> bytes((std::istreambuf_iterator<char>(in)),
                                         std::istreambuf_iterator<char>());
  ByteReader r(bytes);
  auto fail = [&](const std::string& what) {
    file.error = std::string(kReferencePath) + ", byte offset " + std::to_string(r.offset()) +
                 ": " + what;
    file.sections.clear();
    return file;
  };
  if (!r.have(8) || std::memcmp(bytes.data(), kMagic, 8) != 0) return fail("bad magic");
  r.skip(8);
  std::uint32_t format = 0, inputs = 0, count = 0;
  if (!r.u32(format) || format != kFormatVersion)
    return fail("unsupported format version " + std::to_string(format));
  if (!r.u32(inputs) || inputs != ref::kInputsVersion) {
    return fail("written for inputs version " + std::to_string(inputs) +
                " but reference_cases.h is version " + std::to_string(ref::kInputsVersion) +
                ": regenerate the file");
  }
  if (!r.str(file.producer)) return fail("truncated producer");
  if (!r.u32(count)) return fail("truncated section count");
  for (std::uint32_t k = 0; k < count; ++k) {
    Section s;
    if (!r.str(s.name) || !r.u64(s.cases) || !r.u32(s.doubles_per_case))
      return fail("truncated header of section " + std::to_string(k));
    const std::uint64_t n = s.cases * s.doubles_per_case;
    if (s.doubles_per_case == 0 || !r.have(n * 8))
      return fail("section '" + s.name + "' is truncated");
    s.values.resize(n);
    for (double& d : s.values) r.f64(d);
    file.sections.emplace(s.name, std::move(s));
  }
  if (r.have(1)) return fail("trailing bytes after the last section");
  return file;
}

const ReferenceFile& reference() {
  static const ReferenceFile file = load_reference();
  return file;
}

/// Finds a section and checks its shape; the test fails if it cannot.
::testing::AssertionResult get_section(std::string_view name, std::uint32_t doubles_per_case,
                                       const Section*& out) {
  const ReferenceFile& file = reference();
  if (!file.error.empty()) return ::testing::AssertionFailure() << file.error;
  const auto it = file.sections.find(name);
  if (it == file.sections.end())
    return ::testing::AssertionFailure()
           << kReferencePath << " has no section '" << name << "': regenerate it";
  if (it->second.doubles_per_case != doubles_per_case)
    return ::testing::AssertionFailure()
           << "section '" << name << "' has " << it->second.doubles_per_case
           << " doubles per case, expected " << doubles_per_case;
  if (it->second.cases == 0)
    return ::testing::AssertionFailure() << "section '" << name << "' is empty";
  out = &it->second;
  return ::testing::AssertionSuccess();
}

// ---------------------------------------------------------------------------
// Error measures and the per-section report

/// Relative error with an absolute floor: |a − b| / max(1, |b|).
double value_error(double a, double b) { return std::abs(a - b) / std::max(1.0, std::abs(b)); }

/// Angular difference wrapped to [0, π].
double angle_error(double a, double b) { return std::abs(wrap_to_pi(a - b)); }

/// Tracks the worst error of a section and prints it.
class Worst {
 public:
  Worst(std::string section, double tolerance) : section_(std::move(section)), tol_(tolerance) {}

  void add(double err, std::size_t case_index, std::string_view component) {
    ++checked_;
    if (!(err <= tol_)) ++over_;
    if (!(err <= worst_)) {  // NaN becomes the worst
      worst_ = err;
      case_ = case_index;
      component_ = component;
    }
  }

  /// A note printed with the result (e.g. cases handled specially).
  void note(std::string text) { notes_.push_back(std::move(text)); }

  /// Prints the summary and fails the test if any error exceeded the tolerance.
  void finish() const {
    std::printf("[ mrpt     ] %-28s worst %.3e (case %zu, %s), tolerance %.0e, %zu values\n",
                section_.c_str(), worst_, case_, component_.c_str(), tol_, checked_);
    for (const std::string& n : notes_) std::printf("[ mrpt     ] %-28s %s\n", "", n.c_str());
    EXPECT_EQ(over_, 0u) << section_ << ": " << over_ << " of " << checked_
                         << " values differ from MRPT by more than " << tol_ << "; worst "
                         << worst_ << " at case " << case_ << " (" << component_ << ")";
  }

 private:
  std::string section_;
  double tol_;
  double worst_ = 0.0;
  std::size_t case_ = 0;
  std::string component_ = "-";
  std::size_t checked_ = 0;
  std::size_t over_ = 0;
  std::vector<std::string> notes_;
};

void compare_pose2(Worst& w, std::size_t i, const Pose2& p, const double* m) {
  w.add(value_error(p.x(), m[0]), i, "x");
  w.add(value_error(p.y(), m[1]), i, "y");
  w.add(angle_error(p.phi(), m[2]), i, "phi");
}

void compare_xyz(Worst& w, std::size_t i, double x, double y, double z, const double* m) {
  w.add(value_error(x, m[0]), i, "x");
  w.add(value_error(y, m[1]), i, "y");
  w.add(value_error(z, m[2]), i, "z");
}

void compare_ypr(Worst& w, std::size_t i, const YawPitchRoll& a, const double* m) {
  w.add(angle_error(a.yaw, m[0]), i, "yaw");
  w.add(angle_error(a.pitch, m[1]), i, "pitch");
  w.add(angle_error(a.roll, m[2]), i, "roll");
}

void compare_pose3(Worst& w, std::size_t i, const Pose3& p, const double* m) {
  compare_xyz(w, i, p.x(), p.y(), p.z(), m);
  compare_ypr(w, i, p.yaw_pitch_roll(), m + 3);
}

/// Quaternion (w, x, y, z) against MRPT's, up to sign.
void compare_quat_up_to_sign(Worst& w, std::size_t i, const Eigen::Quaterniond& q,
                             const double* m) {
  const Eigen::Vector4d a(q.w(), q.x(), q.y(), q.z());
  const Eigen::Vector4d b(m[0], m[1], m[2], m[3]);
  w.add(std::min((a - b).cwiseAbs().maxCoeff(), (a + b).cwiseAbs().maxCoeff()), i, "q");
}

/// Quaternion against MRPT's, sign included.
void compare_quat(Worst& w, std::size_t i, const Eigen::Quaterniond& q, const double* m) {
  const Eigen::Vector4d a(q.w(), q.x(), q.y(), q.z());
  const Eigen::Vector4d b(m[0], m[1], m[2], m[3]);
  w.add((a - b).cwiseAbs().maxCoeff(), i, "q");
}

/// Full symmetric matrix from MRPT's upper triangle.
template <int N>
Eigen::Matrix<double, N, N> from_upper(const double* u) {
  Eigen::Matrix<double, N, N> m;
  for (int r = 0; r < N; ++r)
    for (int c = r; c < N; ++c) {
      const double v = u[ref::upper_triangle_index(N, r, c)];
      m(r, c) = v;
      m(c, r) = v;
    }
  return m;
}

/// max |C − M| / ‖M‖_F.
template <int N>
void compare_cov(Worst& w, std::size_t i, const Eigen::Matrix<double, N, N>& c,
                 const Eigen::Matrix<double, N, N>& m) {
  w.add((c - m).cwiseAbs().maxCoeff() / m.norm(), i, "cov");
}

template <std::size_t N>
Eigen::Matrix<double, int{N}, int{N}> to_eigen(const ref::MatN<N>& a) {
  Eigen::Matrix<double, int{N}, int{N}> m;
  for (std::size_t r = 0; r < N; ++r)
    for (std::size_t c = 0; c < N; ++c)
      m(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(c)) = a[r * N + c];
  return m;
}

Pose2 rove_pose2(const ref::Pose2In& p) { return Pose2(p[0], p[1], p[2]); }
Pose3 rove_pose3(const ref::Pose3In& p) { return Pose3(p[0], p[1], p[2], p[3], p[4], p[5]); }
Pose3Quat rove_pose3quat(const ref::Pose3QuatIn& p) {
  return Pose3Quat(p[0], p[1], p[2], p[3], p[4], p[5], p[6]);
}
Eigen::Matrix3d rove_matrix3(const ref::Mat3& r) {
  Eigen::Matrix3d m;
  m << r[0], r[1], r[2], r[3], r[4], r[5], r[6], r[7], r[8];
  return m;
}

/// Runs `body(rng, case_index, mrpt_row)` over every case of a section.
template <class Body>
void for_each_case(const Section& s, Body&& body) {
  ref::SplitMix64 rng = ref::section_rng(s.name);
  for (std::size_t i = 0; i < s.cases; ++i) body(rng, i, s.row(i));
}

#define ROVE_GET_SECTION(var, name, dpc) \
  const Section* var = nullptr;          \
  ASSERT_TRUE(get_section(name, dpc, var))

// ---------------------------------------------------------------------------
// The file itself

TEST(MrptReference, FileIsPresentAndComplete) {
  const ReferenceFile& file = reference();
  ASSERT_TRUE(file.error.empty()) << file.error;
  EXPECT_EQ(file.producer, "MRPT 2.5.8");
  EXPECT_EQ(file.sections.size(), 27u);
  for (const auto& [name, s] : file.sections) EXPECT_GE(s.cases, 1000u) << name;
}

// ---------------------------------------------------------------------------
// 2D

TEST(MrptReference, Pose2PlusPose2) {
  ROVE_GET_SECTION(s, "pose2_plus_pose2", 3);
  Worst w(s->name, kTolerance);
  for_each_case(*s, [&](auto& rng, std::size_t i, const double* m) {
    const auto a = ref::pose2(rng);
    const auto b = ref::pose2(rng);
    compare_pose2(w, i, rove_pose2(a) + rove_pose2(b), m);
  });
  w.finish();
}

TEST(MrptReference, Pose2MinusPose2) {
  ROVE_GET_SECTION(s, "pose2_minus_pose2", 3);
  Worst w(s->name, kTolerance);
  for_each_case(*s, [&](auto& rng, std::size_t i, const double* m) {
    const auto a = ref::pose2(rng);
    const auto b = ref::pose2(rng);
    compare_pose2(w, i, rove_pose2(a) - rove_pose2(b), m);
  });
  w.finish();
}

TEST(MrptReference, Pose2PlusPoint2) {
  ROVE_GET_SECTION(s, "pose2_plus_point2", 2);
  Worst w(s->name, kTolerance);
  for_each_case(*s, [&](auto& rng, std::size_t i, const double* m) {
    const auto a = ref::pose2(rng);
    const auto p = ref::point2(rng);
    const Point2 r = rove_pose2(a) + Point2(p[0], p[1]);
    w.add(value_error(r.x, m[0]), i, "x");
    w.add(value_error(r.y, m[1]), i, "y");
  });
  w.finish();
}

TEST(MrptReference, Point2MinusPose2) {
  ROVE_GET_SECTION(s, "point2_minus_pose2", 2);
  Worst w(s->name, kTolerance);
  for_each_case(*s, [&](auto& rng, std::size_t i, const double* m) {
    const auto p = ref::point2(rng);
    const auto a = ref::pose2(rng);
    const Point2 r = Point2(p[0], p[1]) - rove_pose2(a);
    w.add(value_error(r.x, m[0]), i, "x");
    w.add(value_error(r.y, m[1]), i, "y");
  });
  w.finish();
}

// ---------------------------------------------------------------------------
// 3D, yaw/pitch/roll

TEST(MrptReference, Pose3PlusPose3) {
  ROVE_GET_SECTION(s, "pose3_plus_pose3", 6);
  Worst w(s->name, kTolerance);
  for_each_case(*s, [&](auto& rng, std::size_t i, const double* m) {
    const auto a = ref::pose3(rng);
    const auto b = ref::pose3(rng);
    compare_pose3(w, i, rove_pose3(a) + rove_pose3(b), m);
  });
  w.finish();
}

TEST(MrptReference, Pose3MinusPose3) {
  ROVE_GET_SECTION(s, "pose3_minus_pose3", 6);
  Worst w(s->name, kTolerance);
  for_each_case(*s, [&](auto& rng, std::size_t i, const double* m) {
    const auto a = ref::pose3(rng);
    const auto b = ref::pose3(rng);
    compare_pose3(w, i, rove_pose3(a) - rove_pose3(b), m);
  });
  w.finish();
}

TEST(MrptReference, Pose3PlusPoint3) {
  ROVE_GET_SECTION(s, "pose3_plus_point3", 3);
  Worst w(s->name, kTolerance);
  for_each_case(*s, [&](auto& rng, std::size_t i, const double* m) {
    const auto a = ref::pose3(rng);
    const auto p = ref::point3(rng);
    const Point3 r = rove_pose3(a) + Point3(p[0], p[1], p[2]);
    compare_xyz(w, i, r.x, r.y, r.z, m);
  });
  w.finish();
}

TEST(MrptReference, Point3MinusPose3) {
  ROVE_GET_SECTION(s, "point3_minus_pose3", 3);
  Worst w(s->name, kTolerance);
  for_each_case(*s, [&](auto& rng, std::size_t i, const double* m) {
    const auto p = ref::point3(rng);
    const auto a = ref::pose3(rng);
    const Point3 r = Point3(p[0], p[1], p[2]) - rove_pose3(a);
    compare_xyz(w, i, r.x, r.y, r.z, m);
  });
  w.finish();
}

TEST(MrptReference, Pose3Inverse) {
  ROVE_GET_SECTION(s, "pose3_inverse", 6);
  Worst w(s->name, kTolerance);
  for_each_case(*s, [&](auto& rng, std::size_t i, const double* m) {
    const auto a = ref::pose3(rng);
    compare_pose3(w, i, -rove_pose3(a), m);
  });
  w.finish();
}

TEST(MrptReference, Pose2PlusPose3) {
  ROVE_GET_SECTION(s, "pose2_plus_pose3", 6);
  Worst w(s->name, kTolerance);
  for_each_case(*s, [&](auto& rng, std::size_t i, const double* m) {
    const auto a = ref::pose2(rng);
    const auto b = ref::pose3(rng);
    compare_pose3(w, i, rove_pose2(a) + rove_pose3(b), m);
  });
  w.finish();
}

TEST(MrptReference, Pose3PlusPose2) {
  ROVE_GET_SECTION(s, "pose3_plus_pose2", 6);
  Worst w(s->name, kTolerance);
  for_each_case(*s, [&](auto& rng, std::size_t i, const double* m) {
    const auto a = ref::pose3(rng);
    const auto b = ref::pose2(rng);
    compare_pose3(w, i, rove_pose3(a) + rove_pose2(b), m);
  });
  w.finish();
}

// ---------------------------------------------------------------------------
// 3D, quaternions

TEST(MrptReference, Pose3QuatPlusPose3Quat) {
  ROVE_GET_SECTION(s, "pose3quat_plus_pose3quat", 7);
  Worst w(s->name, kTolerance);
  for_each_case(*s, [&](auto& rng, std::size_t i, const double* m) {
    const auto a = ref::pose3quat(rng);
    const auto b = ref::pose3quat(rng);
    const Pose3Quat r = rove_pose3quat(a) + rove_pose3quat(b);
    compare_xyz(w, i, r.x(), r.y(), r.z(), m);
    // MRPT normalizes products to qw ≥ 0 (CQuaternion::normalize calls
    // ensurePositiveRealPart), so the sign is compared too.
    compare_quat(w, i, r.quaternion(), m + 3);
  });
  w.finish();
}

TEST(MrptReference, Pose3QuatMinusPose3Quat) {
  ROVE_GET_SECTION(s, "pose3quat_minus_pose3quat", 7);
  Worst w(s->name, kTolerance);
  for_each_case(*s, [&](auto& rng, std::size_t i, const double* m) {
    const auto a = ref::pose3quat(rng);
    const auto b = ref::pose3quat(rng);
    const Pose3Quat r = rove_pose3quat(a) - rove_pose3quat(b);
    compare_xyz(w, i, r.x(), r.y(), r.z(), m);
    compare_quat(w, i, r.quaternion(), m + 3);
  });
  w.finish();
}

TEST(MrptReference, Pose3QuatPlusPoint3) {
  ROVE_GET_SECTION(s, "pose3quat_plus_point3", 3);
  Worst w(s->name, kTolerance);
  for_each_case(*s, [&](auto& rng, std::size_t i, const double* m) {
    const auto a = ref::pose3quat(rng);
    const auto p = ref::point3(rng);
    const Point3 r = rove_pose3quat(a) + Point3(p[0], p[1], p[2]);
    compare_xyz(w, i, r.x, r.y, r.z, m);
  });
  w.finish();
}

TEST(MrptReference, Point3MinusPose3Quat) {
  ROVE_GET_SECTION(s, "point3_minus_pose3quat", 3);
  Worst w(s->name, kTolerance);
  for_each_case(*s, [&](auto& rng, std::size_t i, const double* m) {
    const auto p = ref::point3(rng);
    const auto a = ref::pose3quat(rng);
    const Point3 r = Point3(p[0], p[1], p[2]) - rove_pose3quat(a);
    compare_xyz(w, i, r.x, r.y, r.z, m);
  });
  w.finish();
}

// ---------------------------------------------------------------------------
// Rotation conversions

TEST(MrptReference, Pose3ToPose3Quat) {
  ROVE_GET_SECTION(s, "pose3_to_pose3quat", 4);
  Worst w(s->name, kTolerance);
  for_each_case(*s, [&](auto& rng, std::size_t i, const double* m) {
    const auto a = ref::pose3(rng);
    // MRPT's half-angle formula does not canonicalize the sign
    // (TPose3D::getAsQuaternion); rove follows it, so the sign is compared.
    compare_quat(w, i, Pose3Quat(rove_pose3(a)).quaternion(), m);
  });
  w.finish();
}

TEST(MrptReference, Pose3QuatToPose3) {
  ROVE_GET_SECTION(s, "pose3quat_to_pose3", 3);
  Worst w(s->name, kTolerance);
  for_each_case(*s, [&](auto& rng, std::size_t i, const double* m) {
    const auto a = ref::pose3quat(rng);
    compare_ypr(w, i, Pose3(rove_pose3quat(a)).yaw_pitch_roll(), m);
  });
  w.finish();
}

TEST(MrptReference, YawPitchRollFromRotation) {
  ROVE_GET_SECTION(s, "ypr_from_rotation", 3);
  Worst w(s->name, kTolerance);
  for_each_case(*s, [&](auto& rng, std::size_t i, const double* m) {
    const Eigen::Matrix3d R = rove_matrix3(ref::rotation_from_quaternion(ref::quaternion(rng)));
    compare_ypr(w, i, Pose3(R, Eigen::Vector3d::Zero()).yaw_pitch_roll(), m);
  });
  w.finish();
}

TEST(MrptReference, YawPitchRollFromRotationAtGimbalLock) {
  ROVE_GET_SECTION(s, "ypr_from_rotation_gimbal", 3);
  Worst w(s->name, kTolerance);
  for_each_case(*s, [&](auto& rng, std::size_t i, const double* m) {
    const Eigen::Matrix3d R = rove_matrix3(ref::gimbal_rotation(rng, i));
    compare_ypr(w, i, Pose3(R, Eigen::Vector3d::Zero()).yaw_pitch_roll(), m);
  });
  w.finish();
}

// ---------------------------------------------------------------------------
// Gaussian PDFs

TEST(MrptReference, Pose2GaussianPlus) {
  ROVE_GET_SECTION(s, "pose2_gaussian_plus", 6);
  Worst w(s->name, kTolerance);
  for_each_case(*s, [&](auto& rng, std::size_t i, const double* m) {
    const auto a = ref::pose2_gaussian(rng);
    const auto b = ref::pose2_gaussian(rng);
    const Pose2Gaussian r = Pose2Gaussian(rove_pose2(a.mean), to_eigen<3>(a.cov)) +
                            Pose2Gaussian(rove_pose2(b.mean), to_eigen<3>(b.cov));
    compare_cov<3>(w, i, r.covariance(), from_upper<3>(m));
  });
  w.finish();
}

TEST(MrptReference, Pose2GaussianInverse) {
  ROVE_GET_SECTION(s, "pose2_gaussian_inverse", 6);
  Worst w(s->name, kTolerance);
  for_each_case(*s, [&](auto& rng, std::size_t i, const double* m) {
    const auto a = ref::pose2_gaussian(rng);
    const Pose2Gaussian r = inverse(Pose2Gaussian(rove_pose2(a.mean), to_eigen<3>(a.cov)));
    compare_cov<3>(w, i, r.covariance(), from_upper<3>(m));
  });
  w.finish();
}

/// Half-angle quaternion (w, x, y, z) of yaw/pitch/roll exactly as MRPT's
/// TPose3D::getAsQuaternion computes it (sign not canonicalized).
Eigen::Vector4d mrpt_quat_of_ypr(const ref::Pose3In& p) {
  const Eigen::Quaterniond q = quaternion_from_ypr(p[3], p[4], p[5]);
  return {q.w(), q.x(), q.y(), q.z()};
}

/// (w, x, y, z) Hamilton product.
Eigen::Vector4d hamilton(const Eigen::Vector4d& a, const Eigen::Vector4d& b) {
  return {a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3],
          a[0] * b[1] + b[0] * a[1] + a[2] * b[3] - b[2] * a[3],
          a[0] * b[2] + b[0] * a[2] + a[3] * b[1] - b[3] * a[1],
          a[0] * b[3] + b[0] * a[3] + a[1] * b[2] - b[1] * a[2]};
}

/// MRPT composes and inverts CPose3DPDFGaussian through CPose3DQuatPDFGaussian
/// (CPose3DPDFGaussian::operator+= and ::inverse, CPose3DPDFGaussian.cpp).
/// When the raw quaternion product of that detour has qw < 0,
/// CQuaternion::crossProduct → normalize() → ensurePositiveRealPart() flips
/// the mean's sign, but the covariance keeps the Jacobian of the unflipped
/// product (CPose3DQuatPDF::jacobiansPoseComposition); the conversion back to
/// yaw/pitch/roll then evaluates dr/dq at the flipped mean, and dr/dq is odd
/// in q, so the translation–angle block of MRPT's result has the wrong sign.
/// This returns MRPT's covariance with that block's sign restored when
/// `mrpt_flipped`, i.e. the covariance MRPT's own Jacobians mean to compute.
Eigen::Matrix<double, 6, 6> mrpt_pose3_cov_sign_restored(const double* m, bool mrpt_flipped) {
  Eigen::Matrix<double, 6, 6> c = from_upper<6>(m);
  if (mrpt_flipped) {
    c.topRightCorner<3, 3>() *= -1.0;
    c.bottomLeftCorner<3, 3>() *= -1.0;
  }
  return c;
}

/// MRPT's yaw/pitch/roll from a quaternion (CQuaternion::rpy_and_jacobian,
/// used by CPose3DPDFGaussian(CPose3DQuatPDFGaussian)) switches to a
/// gimbal-lock approximation when |qw·qy − qx·qz| > 0.49999, i.e. within
/// about 0.36° of pitch ±90°: roll is forced to 0 and pitch to ±π/2 there,
/// and the Jacobian is that of the approximation. rove's exact covariance
/// cannot agree with it in that band; such cases are counted, not compared.
bool in_mrpt_rpy_gimbal_band(const Eigen::Quaterniond& q) {
  const Eigen::Quaterniond u = q.normalized();
  return std::abs(u.w() * u.y() - u.x() * u.z()) > 0.49999;
}

TEST(MrptReference, Pose3GaussianPlus) {
  ROVE_GET_SECTION(s, "pose3_gaussian_plus", 21);
  Worst w(s->name, kTolerance);
  std::size_t flipped = 0, gimbal = 0;
  for_each_case(*s, [&](auto& rng, std::size_t i, const double* m) {
    const auto a = ref::pose3_gaussian(rng);
    const auto b = ref::pose3_gaussian(rng);
    const Pose3Gaussian r = Pose3Gaussian(rove_pose3(a.mean), to_eigen<6>(a.cov)) +
                            Pose3Gaussian(rove_pose3(b.mean), to_eigen<6>(b.cov));
    const Eigen::Vector4d raw = hamilton(mrpt_quat_of_ypr(a.mean), mrpt_quat_of_ypr(b.mean));
    if (in_mrpt_rpy_gimbal_band(Eigen::Quaterniond(raw[0], raw[1], raw[2], raw[3]))) {
      ++gimbal;
      return;
    }
    const bool flip = raw[0] < 0;
    flipped += flip;
    compare_cov<6>(w, i, r.covariance(), mrpt_pose3_cov_sign_restored(m, flip));
  });
  w.note(std::to_string(flipped) + " cases with MRPT's translation-angle sign restored, " +
         std::to_string(gimbal) + " in MRPT's rpy gimbal band skipped");
  w.finish();
}

TEST(MrptReference, Pose3GaussianInverse) {
  ROVE_GET_SECTION(s, "pose3_gaussian_inverse", 21);
  Worst w(s->name, kTolerance);
  std::size_t flipped = 0, gimbal = 0;
  for_each_case(*s, [&](auto& rng, std::size_t i, const double* m) {
    const auto a = ref::pose3_gaussian(rng);
    const Pose3Gaussian r = inverse(Pose3Gaussian(rove_pose3(a.mean), to_eigen<6>(a.cov)));
    // MRPT: (0 − a) = inverse(a7) ⊕ 0₇; the raw product is conj(q(a)).
    const Eigen::Vector4d q = mrpt_quat_of_ypr(a.mean);
    if (in_mrpt_rpy_gimbal_band(Eigen::Quaterniond(q[0], -q[1], -q[2], -q[3]))) {
      ++gimbal;
      return;
    }
    const bool flip = q[0] < 0;
    flipped += flip;
    compare_cov<6>(w, i, r.covariance(), mrpt_pose3_cov_sign_restored(m, flip));
  });
  w.note(std::to_string(flipped) + " cases with MRPT's translation-angle sign restored, " +
         std::to_string(gimbal) + " in MRPT's rpy gimbal band skipped");
  w.finish();
}

/// S·C·S with S = diag(1, 1, 1, s, s, s, s): the covariance of the same
/// Gaussian written with the quaternion's sign changed by s.
Eigen::Matrix<double, 7, 7> with_quat_sign(const Eigen::Matrix<double, 7, 7>& c, double s) {
  Eigen::Matrix<double, 7, 1> d;
  d << 1, 1, 1, s, s, s, s;
  return d.asDiagonal() * c * d.asDiagonal();
}

Eigen::Vector4d as_vec(const Eigen::Quaterniond& q) { return {q.w(), q.x(), q.y(), q.z()}; }

TEST(MrptReference, Pose3QuatGaussianPlus) {
  ROVE_GET_SECTION(s, "pose3quat_gaussian_plus", 32);
  Worst w(s->name, kTolerance);
  std::size_t flipped = 0;
  for_each_case(*s, [&](auto& rng, std::size_t i, const double* m) {
    const auto a = ref::pose3quat_gaussian(rng);
    const auto b = ref::pose3quat_gaussian(rng);
    const Pose3QuatGaussian r =
        Pose3QuatGaussian(rove_pose3quat(a.mean), to_eigen<7>(a.cov)) +
        Pose3QuatGaussian(rove_pose3quat(b.mean), to_eigen<7>(b.cov));
    compare_quat(w, i, r.mean().quaternion(), m);
    // MRPT's mean is the product normalized to qw ≥ 0, but its covariance
    // uses the Jacobian of the unflipped product (see
    // mrpt_pose3_cov_sign_restored): compare in the sign of the raw product.
    const Eigen::Vector4d raw =
        hamilton({a.mean[3], a.mean[4], a.mean[5], a.mean[6]},
                 {b.mean[3], b.mean[4], b.mean[5], b.mean[6]});
    const double sign = as_vec(r.mean().quaternion()).dot(raw) < 0 ? -1.0 : 1.0;
    flipped += raw[0] < 0;
    compare_cov<7>(w, i, with_quat_sign(r.covariance(), sign), from_upper<7>(m + 4));
  });
  w.note(std::to_string(flipped) +
         " cases where MRPT's covariance is in the sign of the raw product, not of its mean");
  w.finish();
}

TEST(MrptReference, Pose3QuatGaussianInverse) {
  ROVE_GET_SECTION(s, "pose3quat_gaussian_inverse", 32);
  Worst w(s->name, kTolerance);
  for_each_case(*s, [&](auto& rng, std::size_t i, const double* m) {
    const auto a = ref::pose3quat_gaussian(rng);
    const Pose3QuatGaussian r =
        inverse(Pose3QuatGaussian(rove_pose3quat(a.mean), to_eigen<7>(a.cov)));
    compare_quat_up_to_sign(w, i, r.mean().quaternion(), m);
    const Eigen::Vector4d mq(m[0], m[1], m[2], m[3]);
    const double sign = as_vec(r.mean().quaternion()).dot(mq) < 0 ? -1.0 : 1.0;
    compare_cov<7>(w, i, with_quat_sign(r.covariance(), sign), from_upper<7>(m + 4));
  });
  w.finish();
}

TEST(MrptReference, Pose3GaussianToQuat) {
  ROVE_GET_SECTION(s, "pose3_gaussian_to_quat", 32);
  Worst w(s->name, kTolerance);
  for_each_case(*s, [&](auto& rng, std::size_t i, const double* m) {
    const auto a = ref::pose3_gaussian(rng);
    const Pose3QuatGaussian r =
        to_quat_gaussian(Pose3Gaussian(rove_pose3(a.mean), to_eigen<6>(a.cov)));
    compare_quat(w, i, r.mean().quaternion(), m);
    compare_cov<7>(w, i, r.covariance(), from_upper<7>(m + 4));
  });
  w.finish();
}

TEST(MrptReference, Pose3QuatGaussianToEuler) {
  ROVE_GET_SECTION(s, "pose3quat_gaussian_to_euler", 21);
  Worst w(s->name, kTolerance);
  std::size_t gimbal = 0;
  for_each_case(*s, [&](auto& rng, std::size_t i, const double* m) {
    const auto a = ref::pose3quat_gaussian(rng);
    const Pose3Gaussian r =
        to_euler_gaussian(Pose3QuatGaussian(rove_pose3quat(a.mean), to_eigen<7>(a.cov)));
    if (in_mrpt_rpy_gimbal_band(Eigen::Quaterniond(a.mean[3], a.mean[4], a.mean[5], a.mean[6]))) {
      ++gimbal;
      return;
    }
    compare_cov<6>(w, i, r.covariance(), from_upper<6>(m));
  });
  w.note(std::to_string(gimbal) + " cases in MRPT's rpy gimbal band skipped");
  w.finish();
}

}  // namespace
}  // namespace rove
