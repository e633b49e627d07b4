#pragma once
/// \file
/// Scalar coefficients of the closed-form exp/log/Jacobian expressions of
/// SO(2), SE(2), SO(3), SE(3), with Taylor expansions below a small-angle
/// threshold where the closed forms are 0/0 or lose every significant digit.
///
/// The closed forms are used from the threshold upward. Their cancellation
/// error grows as eps/θ^k, but every coefficient below multiplies a product of
/// k skew matrices of θ (size θ^k), so the absolute error in the assembled
/// matrices stays at the rounding level; the Taylor branch exists to avoid
/// division by (nearly) zero and underflow. With terms through θ⁶, truncation
/// at the threshold is below 1e-16 (double, θ < 0.05) and 1e-11 (float,
/// θ < 0.2) relative to the leading term.

#include <cmath>
#include <type_traits>

#include <Eigen/Core>

#include "rove/math/types.h"

namespace rove::detail {

/// Angles (radians) below which the Taylor branches are used.
template <typename T>
inline constexpr T kTaylorThreshold = std::is_same_v<T, float> ? T(0.2) : T(0.05);

/// Skew-symmetric matrix [v]× with [v]× p = v × p.
template <typename T>
inline Matrix3<T> skew(const Vector3<T>& v) {
  Matrix3<T> m;
  m << T(0), -v.z(), v.y(),  //
      v.z(), T(0), -v.x(),   //
      -v.y(), v.x(), T(0);
  return m;
}

/// The three coefficients shared by the SO(3) exponential, its Jacobians and
/// the SE(2)/SE(3) translation maps, at angle θ (any sign):
///   sinc            = sin θ / θ
///   one_minus_cos   = (1 − cos θ) / θ²
///   theta_minus_sin = (θ − sin θ) / θ³
template <typename T>
struct RotationCoefficients {
  T sinc;
  T one_minus_cos;
  T theta_minus_sin;
};

/// Computes RotationCoefficients at θ.
template <typename T>
inline RotationCoefficients<T> rotation_coefficients(T theta) {
  const T t2 = theta * theta;
  if (std::abs(theta) < kTaylorThreshold<T>) {
    const T t4 = t2 * t2;
    const T t6 = t4 * t2;
    return {T(1) - t2 / T(6) + t4 / T(120) - t6 / T(5040),
            T(0.5) - t2 / T(24) + t4 / T(720) - t6 / T(40320),
            T(1) / T(6) - t2 / T(120) + t4 / T(5040) - t6 / T(362880)};
  }
  const T s = std::sin(theta);
  const T c = std::cos(theta);
  return {s / theta, (T(1) - c) / t2, (theta - s) / (t2 * theta)};
}

/// Coefficient of [θ]×² in the inverse Jacobians of SO(3) (Solà et al. 2018,
/// Eqs. 144 and 146):  1/θ² − (1 + cos θ) / (2 θ sin θ),
/// evaluated as 1/θ² − cot(θ/2) / (2θ), which stays finite at θ = π.
/// Precondition (caller): 0 ≤ θ < 2π.
template <typename T>
inline T inverse_jacobian_coefficient(T theta) {
  const T t2 = theta * theta;
  if (theta < kTaylorThreshold<T>) {
    const T t4 = t2 * t2;
    return T(1) / T(12) + t2 / T(720) + t4 / T(30240) + t4 * t2 / T(1209600);
  }
  const T half = theta / T(2);
  return T(1) / t2 - std::cos(half) / (std::sin(half) * T(2) * theta);
}

/// Same coefficient computed from a unit quaternion's parts: given θ and
/// w = cos(θ/2) ≥ 0, n = sin(θ/2) ≥ 0, returns 1/θ² − w / (2 n θ).
template <typename T>
inline T inverse_jacobian_coefficient_from_half_angle(T theta, T w, T n) {
  const T t2 = theta * theta;
  if (theta < kTaylorThreshold<T>) {
    const T t4 = t2 * t2;
    return T(1) / T(12) + t2 / T(720) + t4 / T(30240) + t4 * t2 / T(1209600);
  }
  return T(1) / t2 - w / (T(2) * n * theta);
}

/// The two higher-order coefficients of the SE(3) block Q(ρ, θ) (Solà et al.
/// 2018, Eq. 180; Barfoot & Furgale 2014, Eq. 102):
///   c4 = (θ² + 2 cos θ − 2) / (2 θ⁴)
///   c5 = (2θ − 3 sin θ + θ cos θ) / (2 θ⁵)
template <typename T>
struct SE3QCoefficients {
  T c4;
  T c5;
};

/// Computes SE3QCoefficients at θ ≥ 0.
template <typename T>
inline SE3QCoefficients<T> se3_q_coefficients(T theta) {
  const T t2 = theta * theta;
  const T t4 = t2 * t2;
  if (theta < kTaylorThreshold<T>) {
    const T t6 = t4 * t2;
    return {T(1) / T(24) - t2 / T(720) + t4 / T(40320) - t6 / T(3628800),
            T(1) / T(120) - t2 / T(2520) + t4 / T(120960) - t6 / T(9979200)};
  }
  const T s = std::sin(theta);
  const T c = std::cos(theta);
  return {(t2 + T(2) * c - T(2)) / (T(2) * t4),
          (T(2) * theta - T(3) * s + theta * c) / (T(2) * t4 * theta)};
}

/// First-order renormalization of a nearly-unit quaternion (one Newton step
/// towards 1/‖q‖, no square root): removes the drift a product of two unit
/// quaternions accumulates, leaving |‖q‖ − 1| at O(δ²) for an input at 1 + δ.
template <typename T>
inline void renormalize_near_unit(Quaternion<T>& q) {
  q.coeffs() *= (T(3) - q.coeffs().squaredNorm()) * T(0.5);
}

}  // namespace rove::detail
