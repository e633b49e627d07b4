#pragma once
/// \file
/// Helpers on Eigen::Quaternion<T> (w, x, y, z): checked normalization, the
/// angle between two rotations, and spherical linear interpolation (SLERP,
/// Shoemake 1985, "Animating rotation with quaternion curves"). Conversions
/// to and from rotation vectors are SO3::exp / SO3::log.

#include <cmath>
#include <limits>
#include <type_traits>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "rove/core/check.h"
#include "rove/math/types.h"

namespace rove {

/// q / ‖q‖. Rejects (InvalidArgument) NaN/Inf and a quaternion whose norm is
/// below the smallest normal number (no direction to keep).
template <LieScalar T>
Quaternion<T> normalized_or_throw(const Quaternion<T>& q) {
  ROVE_CHECK_FINITE(q.coeffs());
  const T norm = q.norm();
  ROVE_CHECK_MSG(norm > std::numeric_limits<T>::min(), "cannot normalize a zero quaternion");
  return Quaternion<T>(q.coeffs() / norm);
}

namespace detail {
/// Throws InvalidArgument unless q is finite and |‖q‖ − 1| ≤ kUnitTolerance<T>.
template <LieScalar T>
void check_unit_quaternion(const Quaternion<T>& q, const char* name) {
  ROVE_CHECK_MSG(q.coeffs().allFinite(), "{} has NaN/Inf coefficients", name);
  const T norm = q.norm();
  ROVE_CHECK_MSG(std::abs(norm - T(1)) <= kUnitTolerance<T>,
                 "{} has norm {}, not within {} of 1", name, norm, kUnitTolerance<T>);
}

/// Angle φ ∈ [0, π] between unit 4-vectors a and b, as 2·atan2(‖a − b‖, ‖a + b‖):
/// accurate at every angle, unlike acos(a·b) near 0 and π.
template <typename T>
T angle_between_unit_vectors(const Eigen::Matrix<T, 4, 1>& a, const Eigen::Matrix<T, 4, 1>& b) {
  return T(2) * std::atan2((a - b).norm(), (a + b).norm());
}
}  // namespace detail

/// Angle (radians, in [0, π]) of the rotation q0⁻¹·q1, i.e. the geodesic
/// distance between the rotations q0 and q1. q and −q are the same rotation.
/// Preconditions: q0, q1 finite and of unit norm within kUnitTolerance<T>.
template <LieScalar T>
T rotation_angle_between(const Quaternion<T>& q0, const Quaternion<T>& q1) {
  detail::check_unit_quaternion(q0, "q0");
  detail::check_unit_quaternion(q1, "q1");
  const Eigen::Matrix<T, 4, 1> a = q0.coeffs().normalized();
  Eigen::Matrix<T, 4, 1> b = q1.coeffs().normalized();
  if (a.dot(b) < T(0)) b = -b;
  return T(2) * detail::angle_between_unit_vectors<T>(a, b);
}

/// Spherical linear interpolation between rotations q0 (t = 0) and q1
/// (t = 1) along the shortest arc: q1 is replaced by −q1 when q0·q1 < 0, so
/// the path never exceeds 180° of rotation. The result turns at constant
/// angular velocity: angle(q0, slerp(q0, q1, t)) = t · angle(q0, q1).
///
/// Numerics: the half-angle φ between the 4-vectors comes from atan2 (exact
/// near 0 and near 90°, i.e. rotations ~180° apart, where sin φ ≈ 1); below
/// φ = √eps the interpolation falls back to normalized linear interpolation,
/// whose deviation from SLERP is O(φ³). For rotations exactly 180° apart the
/// shortest arc is not unique; the one through q0·(1−t) + q1·t direction
/// (without sign flip) is returned.
///
/// Preconditions (InvalidArgument otherwise): q0, q1 finite and of unit norm
/// within kUnitTolerance<T>; t finite and in [0, 1]. Returns a unit quaternion.
template <LieScalar T>
Quaternion<T> slerp(const Quaternion<T>& q0, const Quaternion<T>& q1,
                    std::type_identity_t<T> t) {
  ROVE_CHECK_MSG(t >= T(0) && t <= T(1), "slerp parameter t = {} must be in [0, 1]", t);
  detail::check_unit_quaternion(q0, "q0");
  detail::check_unit_quaternion(q1, "q1");
  const Eigen::Matrix<T, 4, 1> a = q0.coeffs().normalized();
  Eigen::Matrix<T, 4, 1> b = q1.coeffs().normalized();
  if (a.dot(b) < T(0)) b = -b;
  const T phi = detail::angle_between_unit_vectors<T>(a, b);  // in [0, π/2]
  Eigen::Matrix<T, 4, 1> r;
  if (phi < std::sqrt(std::numeric_limits<T>::epsilon())) {
    r = (T(1) - t) * a + t * b;
  } else {
    const T s = std::sin(phi);
    r = (std::sin((T(1) - t) * phi) / s) * a + (std::sin(t * phi) / s) * b;
  }
  return Quaternion<T>(r.normalized());
}

}  // namespace rove
