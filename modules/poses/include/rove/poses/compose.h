#pragma once
/// \file
/// Named forms of the pose operators, for generic code: compose(a, b) = a + b,
/// inverse_compose(a, b) = a - b, inverse(p) = -p, with MRPT's result types:
///
/// | a         | b          | a + b (compose) | a - b (inverse_compose) |
/// |-----------|------------|-----------------|-------------------------|
/// | Pose2     | Pose2      | Pose2           | Pose2                   |
/// | Pose2     | Pose3      | Pose3           | Pose3                   |
/// | Pose3     | Pose2/3    | Pose3           | Pose3                   |
/// | Pose3Quat | any pose   | Pose3Quat       | Pose3Quat               |
/// | Pose3     | Pose3Quat  | Pose3           | Pose3                   |
/// | Pose2     | Pose3Quat  | Pose3Quat       | Pose3Quat               |
/// | Pose2     | Point2     | Point2          |                         |
/// | Pose2     | Point3     | Point3          |                         |
/// | Pose3(Q)  | Point2/3   | Point3          |                         |
/// | Point2    | Pose2      |                 | Point2                  |
/// | Point2/3  | Pose3(Q)   |                 | Point3                  |
/// | Point3    | Pose2      |                 | Point3                  |
///
/// The result is 3D when either operand is 3D; between the two 3D pose
/// representations the left operand's is kept.

#include <concepts>
#include <type_traits>
#include <utility>

#include "rove/poses/point2.h"
#include "rove/poses/point3.h"
#include "rove/poses/pose2.h"
#include "rove/poses/pose3.h"
#include "rove/poses/pose3_quat.h"

namespace rove {

/// One of the pose types Pose2, Pose3, Pose3Quat.
template <typename T>
concept PoseType = std::same_as<std::remove_cvref_t<T>, Pose2> ||
                   std::same_as<std::remove_cvref_t<T>, Pose3> ||
                   std::same_as<std::remove_cvref_t<T>, Pose3Quat>;

/// One of the point types Point2, Point3.
template <typename T>
concept PointType =
    std::same_as<std::remove_cvref_t<T>, Point2> || std::same_as<std::remove_cvref_t<T>, Point3>;

/// The type of compose(A, B).
template <PoseType A, typename B>
  requires(PoseType<B> || PointType<B>)
using ComposeResult = decltype(std::declval<const A&>() + std::declval<const B&>());

/// The type of inverse_compose(A, B).
template <typename A, PoseType B>
  requires(PoseType<A> || PointType<A>)
using InverseComposeResult = decltype(std::declval<const A&>() - std::declval<const B&>());

/// a (+) b: pose or point b, given in pose a's frame, in a's parent frame.
template <PoseType A, typename B>
  requires(PoseType<B> || PointType<B>)
ComposeResult<A, B> compose(const A& a, const B& b) noexcept {
  return a + b;
}

/// a (-) b = b^-1 (+) a: pose or point a (parent frame) as seen from pose b.
template <typename A, PoseType B>
  requires(PoseType<A> || PointType<A>)
InverseComposeResult<A, B> inverse_compose(const A& a, const B& b) noexcept {
  return a - b;
}

/// The inverse pose p^-1, such that p^-1 (+) p = identity.
template <PoseType P>
std::remove_cvref_t<P> inverse(const P& p) noexcept {
  return p.inverse();
}

}  // namespace rove
