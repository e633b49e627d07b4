#pragma once
/// \file
/// Distances between any two points or poses, on their positions (MRPT's
/// distanceTo / distance2DTo / distance3DTo). Every point and pose type of
/// rove::poses provides `position_3d(const T&)` (found by argument-dependent
/// lookup) returning its position as a 3D vector, with z = 0 for 2D types.

#include <cmath>
#include <concepts>

#include <Eigen/Core>

namespace rove {

/// A point or pose type: `position_3d(a)` gives its position in meters, z = 0
/// for 2D types.
template <typename T>
concept HasPosition = requires(const T& a) {
  { position_3d(a) } -> std::convertible_to<Eigen::Vector3d>;
};

/// Squared Euclidean distance between the positions of `a` and `b`, in m^2.
/// A 2D operand is taken at z = 0 (as MRPT's sqrDistanceTo).
template <HasPosition A, HasPosition B>
double squared_distance(const A& a, const B& b) {
  return (position_3d(a) - position_3d(b)).squaredNorm();
}

/// Euclidean distance between the positions of `a` and `b`, in meters. A 2D
/// operand is taken at z = 0 (as MRPT's distanceTo).
template <HasPosition A, HasPosition B>
double distance(const A& a, const B& b) {
  return std::sqrt(squared_distance(a, b));
}

/// Distance between the positions of `a` and `b` projected on the XY plane
/// (z ignored), in meters (MRPT's distance2DTo).
template <HasPosition A, HasPosition B>
double distance_2d(const A& a, const B& b) {
  const Eigen::Vector3d d = position_3d(a) - position_3d(b);
  return std::hypot(d.x(), d.y());
}

/// Distance between the 3D positions of `a` and `b`, 2D operands at z = 0, in
/// meters (MRPT's distance3DTo). Same value as distance().
template <HasPosition A, HasPosition B>
double distance_3d(const A& a, const B& b) {
  return distance(a, b);
}

}  // namespace rove
