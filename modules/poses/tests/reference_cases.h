#pragma once
/// \file
/// Deterministic inputs for the MRPT agreement test.
///
/// The reference file data/reference/mrpt-2.5.8-poses.bin stores only the
/// outputs MRPT computed; the inputs are regenerated on both sides (by
/// tools/mrpt_reference and by mrpt_reference_test.cpp) from this header.
/// Everything here is integer arithmetic, IEEE +, −, ×, ÷ and sqrt, plus
/// std::sin/std::cos in the gimbal-lock rotations: the same bits come out of
/// every conforming compiler and standard library (sin/cos up to their last
/// bit, far below the test tolerances).
///
/// Any change to the generation below changes the inputs: bump
/// kInputsVersion, and regenerate the reference file (command in
/// data/reference/README.md). The test refuses a file written for another
/// version.
///
/// Only standard headers: the generator links MRPT and the test links rove,
/// and neither may leak into the other.

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <numbers>
#include <string_view>

namespace rove::reference {

/// Version of the input generation scheme, stored in the reference file.
inline constexpr std::uint32_t kInputsVersion = 1;

/// Half extent of every generated position coordinate, meters: [−10, 10].
inline constexpr double kPositionRange = 10.0;

/// Pitch stays in [−(π/2 − kPitchMargin), π/2 − kPitchMargin] in the general
/// sections. Near ±π/2 yaw and roll are ill-conditioned functions of the
/// rotation (their error grows as 1/cos(pitch)); with 0.1 rad (5.7°) the
/// amplification stays below 10, so 1e-9 comparisons measure the formulas,
/// not the conditioning. Gimbal lock itself has its own section.
inline constexpr double kPitchMargin = 0.1;

/// Standard-deviation scale of generated covariances: positions, meters.
inline constexpr double kSigmaPosition = 0.1;
/// Standard-deviation scale of generated covariances: angles (and rotation
/// vector components), radians.
inline constexpr double kSigmaAngle = 0.05;
/// Regularization of generated covariances, relative to the squared scales:
/// C = D (A Aᵀ / n + kCovEpsilon I) D keeps C well away from singular.
inline constexpr double kCovEpsilon = 1e-3;

/// SplitMix64 (Steele, Lea, Flood, "Fast splittable pseudorandom number
/// generators", OOPSLA 2014): a 64-bit state advanced by a Weyl constant
/// and mixed. Fully specified, so identical everywhere.
class SplitMix64 {
 public:
  /// Starts the sequence from `seed`.
  explicit constexpr SplitMix64(std::uint64_t seed) : state_(seed) {}

  /// Next 64 random bits.
  constexpr std::uint64_t next() {
    std::uint64_t z = (state_ += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }

  /// Uniform double in [0, 1): the top 53 bits times 2^−53, exact.
  constexpr double uniform01() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }

  /// Uniform double in [lo, hi).
  constexpr double uniform(double lo, double hi) { return lo + (hi - lo) * uniform01(); }

 private:
  std::uint64_t state_;
};

/// 64-bit FNV-1a hash of a section name: each section has its own seed, so
/// adding or reordering sections never changes another section's inputs.
constexpr std::uint64_t section_seed(std::string_view name) {
  std::uint64_t h = 0xCBF29CE484222325ull;
  for (const char c : name) {
    h ^= static_cast<unsigned char>(c);
    h *= 0x100000001B3ull;
  }
  return h;
}

/// Random source of one section, seeded from its name.
inline SplitMix64 section_rng(std::string_view name) { return SplitMix64(section_seed(name)); }

/// A position coordinate in [−10, 10) meters.
inline double position(SplitMix64& rng) { return rng.uniform(-kPositionRange, kPositionRange); }

/// An angle in [−π, π) radians.
inline double angle(SplitMix64& rng) { return rng.uniform(-std::numbers::pi, std::numbers::pi); }

/// A pitch in [−(π/2 − kPitchMargin), π/2 − kPitchMargin) radians.
inline double pitch(SplitMix64& rng) {
  const double limit = std::numbers::pi / 2 - kPitchMargin;
  return rng.uniform(-limit, limit);
}

/// (x, y) meters.
using Point2In = std::array<double, 2>;
/// (x, y, z) meters.
using Point3In = std::array<double, 3>;
/// (x, y, phi): meters, radians in [−π, π).
using Pose2In = std::array<double, 3>;
/// (x, y, z, yaw, pitch, roll): meters, radians; R = Rz(yaw)·Ry(pitch)·Rx(roll).
using Pose3In = std::array<double, 6>;
/// (qw, qx, qy, qz): unit quaternion with qw ≥ 0.
using QuatIn = std::array<double, 4>;
/// (x, y, z, qw, qx, qy, qz): meters, unit quaternion with qw ≥ 0.
using Pose3QuatIn = std::array<double, 7>;
/// Row-major 3×3 matrix.
using Mat3 = std::array<double, 9>;
/// Row-major n×n matrix.
template <std::size_t N>
using MatN = std::array<double, N * N>;

/// Random 2D point.
inline Point2In point2(SplitMix64& rng) {
  const double x = position(rng);
  const double y = position(rng);
  return {x, y};
}

/// Random 3D point.
inline Point3In point3(SplitMix64& rng) {
  const double x = position(rng);
  const double y = position(rng);
  const double z = position(rng);
  return {x, y, z};
}

/// Random 2D pose.
inline Pose2In pose2(SplitMix64& rng) {
  const double x = position(rng);
  const double y = position(rng);
  const double phi = angle(rng);
  return {x, y, phi};
}

/// Random 3D pose, pitch kept kPitchMargin away from ±π/2.
inline Pose3In pose3(SplitMix64& rng) {
  const double x = position(rng);
  const double y = position(rng);
  const double z = position(rng);
  const double yaw = angle(rng);
  const double p = pitch(rng);
  const double roll = angle(rng);
  return {x, y, z, yaw, p, roll};
}

/// Random unit quaternion: four uniforms in [−1, 1) normalized (draws with
/// norm below 0.1 are rejected, so the division is well conditioned), then
/// the sign chosen so that qw ≥ 0 (MRPT's CQuaternion convention; MRPT
/// would otherwise flip the input silently).
inline QuatIn quaternion(SplitMix64& rng) {
  for (;;) {
    QuatIn q{};
    for (double& c : q) c = rng.uniform(-1.0, 1.0);
    const double n2 = q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3];
    if (n2 < 0.01) continue;
    const double s = (q[0] < 0 ? -1.0 : 1.0) / std::sqrt(n2);
    for (double& c : q) c *= s;
    return q;
  }
}

/// Random 3D pose with a quaternion rotation.
inline Pose3QuatIn pose3quat(SplitMix64& rng) {
  const Point3In t = point3(rng);
  const QuatIn q = quaternion(rng);
  return {t[0], t[1], t[2], q[0], q[1], q[2], q[3]};
}

/// Rotation matrix of a unit quaternion (qw, qx, qy, qz).
inline Mat3 rotation_from_quaternion(const QuatIn& q) {
  const double w = q[0], x = q[1], y = q[2], z = q[3];
  return {1 - 2 * (y * y + z * z), 2 * (x * y - w * z),     2 * (x * z + w * y),
          2 * (x * y + w * z),     1 - 2 * (x * x + z * z), 2 * (y * z - w * x),
          2 * (x * z - w * y),     2 * (y * z + w * x),     1 - 2 * (x * x + y * y)};
}

/// Rz(yaw)·Ry(pitch)·Rx(roll) from the sines and cosines of the angles.
inline Mat3 rotation_from_ypr_sincos(double cy, double sy, double cp, double sp, double cr,
                                     double sr) {
  return {cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr,
          sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr,
          -sp,     cp * sr,                cp * cr};
}

/// A rotation at or near gimbal lock, for the yaw/pitch/roll extraction.
/// Even cases: pitch exactly ±π/2 (cos 0 and sin ±1 set exactly, so the
/// bottom row is exactly (∓1, 0, 0)); odd cases: pitch = ±(π/2 − δ) with
/// δ = 10^u, u uniform in [−6, −2). Yaw and roll uniform in [−π, π).
inline Mat3 gimbal_rotation(SplitMix64& rng, std::size_t case_index) {
  const double yaw = angle(rng);
  const double roll = angle(rng);
  const double sign = rng.uniform01() < 0.5 ? -1.0 : 1.0;
  const double log_delta = rng.uniform(-6.0, -2.0);
  double cp = 0.0;
  double sp = sign;
  if (case_index % 2 == 1) {
    const double p = sign * (std::numbers::pi / 2 - std::pow(10.0, log_delta));
    cp = std::cos(p);
    sp = std::sin(p);
  }
  return rotation_from_ypr_sincos(std::cos(yaw), std::sin(yaw), cp, sp, std::cos(roll),
                                  std::sin(roll));
}

/// Random symmetric positive-definite n×n matrix with standard deviations
/// of the order of `scales`: C = D (A Aᵀ / n + kCovEpsilon I) D with
/// D = diag(scales), A uniform in [−1, 1) (row-major).
template <std::size_t N>
MatN<N> spd_covariance(SplitMix64& rng, const std::array<double, N>& scales) {
  MatN<N> a{};
  for (double& v : a) v = rng.uniform(-1.0, 1.0);
  MatN<N> c{};
  for (std::size_t i = 0; i < N; ++i) {
    for (std::size_t j = 0; j < N; ++j) {
      double s = 0.0;
      for (std::size_t k = 0; k < N; ++k) s += a[i * N + k] * a[j * N + k];
      s /= static_cast<double>(N);
      if (i == j) s += kCovEpsilon;
      c[i * N + j] = s * (scales[i] * scales[j]);  // bitwise symmetric
    }
  }
  return c;
}

/// Covariance of a Pose2 (x, y, phi): 0.1 m, 0.1 m, 0.05 rad scales.
inline MatN<3> pose2_covariance(SplitMix64& rng) {
  return spd_covariance<3>(rng, {kSigmaPosition, kSigmaPosition, kSigmaAngle});
}

/// Covariance of a Pose3 (x, y, z, yaw, pitch, roll): 0.1 m and 0.05 rad
/// scales.
inline MatN<6> pose3_covariance(SplitMix64& rng) {
  return spd_covariance<6>(rng, {kSigmaPosition, kSigmaPosition, kSigmaPosition, kSigmaAngle,
                                 kSigmaAngle, kSigmaAngle});
}

/// Covariance of a Pose3Quat (x, y, z, qw, qx, qy, qz) about the unit
/// quaternion q, as real estimators produce it: a 6×6 covariance of
/// (translation, rotation vector θ) from pose3_covariance(), mapped through
/// G = diag(I₃, ∂(q ⊗ [1, θ/2])/∂θ), i.e. C₇ = G C₆ Gᵀ. Its quaternion block
/// lies in the tangent space of the unit sphere at q (C₇ q̄ = 0 for the
/// radial direction q̄ = (0, 0, 0, q)), which is what the normalization
/// Jacobians in MRPT's formulas assume; a full-rank 7×7 matrix would give
/// the radial direction a variance no unit quaternion can have.
inline MatN<7> pose3quat_covariance(SplitMix64& rng, const QuatIn& q) {
  const MatN<6> c6 = pose3_covariance(rng);
  const double w = q[0], x = q[1], y = q[2], z = q[3];
  // ∂(q ⊗ [1, θ/2]) / ∂θ, 4×3, rows (w, x, y, z).
  const std::array<double, 12> dq = {-0.5 * x, -0.5 * y, -0.5 * z,  //
                                     0.5 * w,  -0.5 * z, 0.5 * y,   //
                                     0.5 * z,  0.5 * w,  -0.5 * x,  //
                                     -0.5 * y, 0.5 * x,  0.5 * w};
  std::array<double, 7 * 6> g{};
  for (std::size_t i = 0; i < 3; ++i) g[i * 6 + i] = 1.0;
  for (std::size_t i = 0; i < 4; ++i)
    for (std::size_t j = 0; j < 3; ++j) g[(3 + i) * 6 + 3 + j] = dq[i * 3 + j];
  std::array<double, 7 * 6> gc{};
  for (std::size_t i = 0; i < 7; ++i)
    for (std::size_t j = 0; j < 6; ++j) {
      double s = 0.0;
      for (std::size_t k = 0; k < 6; ++k) s += g[i * 6 + k] * c6[k * 6 + j];
      gc[i * 6 + j] = s;
    }
  MatN<7> c7{};
  for (std::size_t i = 0; i < 7; ++i)
    for (std::size_t j = 0; j < 7; ++j) {
      double s = 0.0;
      for (std::size_t k = 0; k < 6; ++k) s += gc[i * 6 + k] * g[j * 6 + k];
      c7[i * 7 + j] = s;
    }
  // Exact symmetry: both triangles from the same products.
  for (std::size_t i = 0; i < 7; ++i)
    for (std::size_t j = 0; j < i; ++j) c7[i * 7 + j] = c7[j * 7 + i];
  return c7;
}

/// A 2D pose Gaussian: mean, then covariance (drawn in that order).
struct Pose2GaussianIn {
  Pose2In mean;
  MatN<3> cov;
};
/// A 3D pose Gaussian (yaw/pitch/roll): mean, then covariance.
struct Pose3GaussianIn {
  Pose3In mean;
  MatN<6> cov;
};
/// A 3D pose Gaussian (quaternion): mean, then covariance about its rotation.
struct Pose3QuatGaussianIn {
  Pose3QuatIn mean;
  MatN<7> cov;
};

/// Random 2D pose Gaussian.
inline Pose2GaussianIn pose2_gaussian(SplitMix64& rng) {
  Pose2GaussianIn g;
  g.mean = pose2(rng);
  g.cov = pose2_covariance(rng);
  return g;
}

/// Random 3D pose Gaussian (yaw/pitch/roll).
inline Pose3GaussianIn pose3_gaussian(SplitMix64& rng) {
  Pose3GaussianIn g;
  g.mean = pose3(rng);
  g.cov = pose3_covariance(rng);
  return g;
}

/// Random 3D pose Gaussian (quaternion).
inline Pose3QuatGaussianIn pose3quat_gaussian(SplitMix64& rng) {
  Pose3QuatGaussianIn g;
  g.mean = pose3quat(rng);
  g.cov = pose3quat_covariance(rng, {g.mean[3], g.mean[4], g.mean[5], g.mean[6]});
  return g;
}

/// Number of doubles in the upper triangle (diagonal included) of n×n.
inline constexpr std::size_t upper_triangle_size(std::size_t n) { return n * (n + 1) / 2; }

/// Index of element (i, j), i ≤ j, in a row-major upper-triangle listing:
/// (0,0), (0,1), ..., (0,n−1), (1,1), ..., (n−1,n−1).
inline constexpr std::size_t upper_triangle_index(std::size_t n, std::size_t i, std::size_t j) {
  return i * n - i * (i - 1) / 2 + (j - i);
}

}  // namespace rove::reference
