#pragma once
/// \file
/// The PointCloudLike concept: "something that holds indexable 2D or 3D
/// points". KdTree, the filters and registration (ICP, GICP, NDT) accept any
/// type that models it, so a caller can run them on its own cloud type
/// without copying into rove::PointCloud first.
///
/// A type C models PointCloudLike when, for `const C& c` and `std::size_t i`,
/// the unqualified calls
///   point_count(c)  -> convertible to std::size_t
///   point_at(c, i)  -> an Eigen fixed-size column vector of 2 or 3 float or
///                      double coordinates (by value or by const reference)
/// are valid. point_at is called only with i < point_count(c). To adapt a
/// type of your own, declare both functions in its namespace (they are found
/// by argument-dependent lookup). This header provides them for
/// rove::PointCloud and for std::vector of Eigen::Vector{2,3}{f,d}.
///
///   struct MyCloud { std::vector<MyPoint> pts; };
///   std::size_t point_count(const MyCloud& c) { return c.pts.size(); }
///   Eigen::Vector3d point_at(const MyCloud& c, std::size_t i) { ... }
///   static_assert(rove::PointCloudLike<MyCloud>);

#include <concepts>
#include <cstddef>
#include <type_traits>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "rove/maps/point_cloud.h"

namespace rove {

/// Number of points of a rove::PointCloud.
inline std::size_t point_count(const PointCloud& c) noexcept { return c.size(); }
/// Point i of a rove::PointCloud, meters.
inline const Eigen::Vector3f& point_at(const PointCloud& c, std::size_t i) noexcept {
  return c[i];
}

/// point_count / point_at for std::vector of Eigen vectors.
template <typename Scalar, int Dim, typename Alloc>
  requires((Dim == 2 || Dim == 3) && (std::is_same_v<Scalar, float> || std::is_same_v<Scalar, double>))
std::size_t point_count(const std::vector<Eigen::Matrix<Scalar, Dim, 1>, Alloc>& c) noexcept {
  return c.size();
}
template <typename Scalar, int Dim, typename Alloc>
  requires((Dim == 2 || Dim == 3) && (std::is_same_v<Scalar, float> || std::is_same_v<Scalar, double>))
const Eigen::Matrix<Scalar, Dim, 1>& point_at(const std::vector<Eigen::Matrix<Scalar, Dim, 1>, Alloc>& c,
                                              std::size_t i) noexcept {
  return c[i];
}

namespace detail {
template <typename V>
concept CloudPointVector =
    (std::is_same_v<V, Eigen::Matrix<float, 2, 1>> || std::is_same_v<V, Eigen::Matrix<float, 3, 1>> ||
     std::is_same_v<V, Eigen::Matrix<double, 2, 1>> || std::is_same_v<V, Eigen::Matrix<double, 3, 1>>);
}  // namespace detail

/// See the file comment.
template <typename C>
concept PointCloudLike = requires(const C& c, std::size_t i) {
  { point_count(c) } -> std::convertible_to<std::size_t>;
  point_at(c, i);
} && detail::CloudPointVector<std::remove_cvref_t<decltype(point_at(std::declval<const C&>(), std::size_t{}))>>;

/// The point type (an Eigen vector) of a cloud type.
template <PointCloudLike C>
using cloud_point_t = std::remove_cvref_t<decltype(point_at(std::declval<const C&>(), std::size_t{}))>;
/// The coordinate type (float or double) of a cloud type.
template <PointCloudLike C>
using cloud_scalar_t = typename cloud_point_t<C>::Scalar;
/// The number of coordinates (2 or 3) of a cloud type.
template <PointCloudLike C>
inline constexpr int cloud_dim_v = cloud_point_t<C>::RowsAtCompileTime;

}  // namespace rove
