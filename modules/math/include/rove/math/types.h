#pragma once
/// \file
/// Fixed-size Eigen aliases and scalar tolerances shared by rove's Lie groups
/// (SO2, SE2, SO3, SE3) and quaternion helpers.

#include <concepts>
#include <type_traits>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace rove {

/// Scalar types the Lie groups are instantiated for.
template <typename T>
concept LieScalar = std::same_as<T, float> || std::same_as<T, double>;

/// Column vector of N scalars.
template <typename T, int N>
using VectorN = Eigen::Matrix<T, N, 1>;
/// 2-vector.
template <typename T>
using Vector2 = Eigen::Matrix<T, 2, 1>;
/// 3-vector.
template <typename T>
using Vector3 = Eigen::Matrix<T, 3, 1>;
/// 6-vector.
template <typename T>
using Vector6 = Eigen::Matrix<T, 6, 1>;
/// 2x2 matrix.
template <typename T>
using Matrix2 = Eigen::Matrix<T, 2, 2>;
/// 3x3 matrix.
template <typename T>
using Matrix3 = Eigen::Matrix<T, 3, 3>;
/// 4x4 matrix.
template <typename T>
using Matrix4 = Eigen::Matrix<T, 4, 4>;
/// 6x6 matrix.
template <typename T>
using Matrix6 = Eigen::Matrix<T, 6, 6>;
/// Quaternion (w, x, y, z); a rotation when of unit norm.
template <typename T>
using Quaternion = Eigen::Quaternion<T>;

/// Largest accepted deviation from unit norm of a quaternion handed to a
/// checked constructor (|‖q‖ − 1| ≤ tolerance), and largest accepted entry of
/// RᵀR − I for a rotation matrix handed to a checked constructor. Inputs within
/// the tolerance are accepted and then normalized exactly; inputs outside it are
/// rejected with InvalidArgument (use the explicit normalizing factories for
/// data that is only approximately unit, e.g. quaternions read from text files).
/// double: 1e-6, float: 1e-4 (about 800 float ulps).
template <LieScalar T>
inline constexpr T kUnitTolerance = std::is_same_v<T, float> ? T(1e-4) : T(1e-6);

/// Default tolerance of the is_approx() comparisons of the Lie groups
/// (Eigen's dummy precision: 1e-12 for double, 1e-5 for float).
template <LieScalar T>
inline T default_approx_tolerance() {
  return Eigen::NumTraits<T>::dummy_precision();
}

}  // namespace rove
