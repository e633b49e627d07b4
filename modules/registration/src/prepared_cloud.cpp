#include "rove/registration/prepared_cloud.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Geometry>

#include "rove/core/check.h"
#include "rove/registration/parallel.h"

namespace rove {

namespace {
struct Nothing {
  Nothing& operator+=(const Nothing&) { return *this; }
};
// Returns the distance to the farthest of the neighbours used (0 if fewer
// than 3 were found); `bound` limits the search (infinite: none).
// `neighbors` (k entries, or null) receives the neighbours, nearest first.
template <typename PointOf>
float local_surface(const KdTree3f& tree, const PointOf& point, const Eigen::Vector3f& query,
                    std::size_t k, double gicp_epsilon, Eigen::Vector3f* normal,
                    Eigen::Matrix3d* covariance, float bound, Neighbor<float>* neighbors = nullptr,
                    Eigen::Vector3d* axis = nullptr);
}  // namespace

PreparedCloud3D::PreparedCloud3D() = default;
PreparedCloud3D::PreparedCloud3D(PreparedCloud3D&&) noexcept = default;
PreparedCloud3D& PreparedCloud3D::operator=(PreparedCloud3D&&) noexcept = default;
PreparedCloud3D::~PreparedCloud3D() = default;

PreparedCloud3D::PreparedCloud3D(std::vector<Eigen::Vector3f> points, const PrepareOptions& options)
    : points_(std::move(points)), options_(options) {
  ROVE_CHECK_GE(options.neighbors, std::size_t{3});
  ROVE_CHECK_MSG(options.gicp_epsilon > 0 && options.gicp_epsilon <= 1,
                 "gicp_epsilon must be in (0, 1], got {}", options.gicp_epsilon);
  ROVE_CHECK_GE(options.num_threads, 1);
  ROVE_CHECK_LT(points_.size(), std::size_t{std::numeric_limits<std::uint32_t>::max()});
  std::erase_if(points_, [](const Eigen::Vector3f& p) { return !p.allFinite(); });
  tree_ = KdTree3f(points_);
  if (points_.empty()) return;
  if (options.normals) normals_.assign(points_.size(), Eigen::Vector3f::Zero());
  if (options.covariances) gicp_axes_.assign(points_.size(), Eigen::Vector3d::Zero());
  if (!options.normals && !options.covariances) return;
  // The tree indexes every point of points_ (all finite), so a neighbour's
  // index is its position in points_.
  const auto point = [this](std::uint32_t j) -> const Eigen::Vector3f& { return points_[j]; };
  // Points are visited in the tree's order, so consecutive queries are
  // close in space, and each search is bounded by what the previous one
  // found: the k neighbours of p, within r of it, are within r + |q − p| of
  // q, so q's k nearest all lie in that ball and the search needs to look
  // nowhere else (the same neighbours as an unbounded search, but for which
  // of several points tied at the k-th distance is kept; far fewer nodes
  // visited). Blocks of the order run in parallel, each from an
  // unbounded first search, so the results do not depend on the threads.
  const std::span<const std::uint32_t> order = tree_.tree_order();
  const std::size_t k = std::min(options.neighbors, points_.size());
  if (options.neighborhoods) {
    neighbors_per_point_ = k;
    neighborhoods_.assign(points_.size() * k, Neighbor<float>{});
  }
  constexpr float kInf = std::numeric_limits<float>::infinity();
  detail::parallel_reduce(order.size(), options.num_threads, Nothing{},
                          [&](std::size_t begin, std::size_t end, Nothing&) {
    float reach = kInf;  // previous query's farthest neighbour, meters
    Eigen::Vector3f prev = Eigen::Vector3f::Zero();
    for (std::size_t t = begin; t < end; ++t) {
      const std::uint32_t i = order[t];
      const Eigen::Vector3f& q = points_[i];
      // A hair above, so rounding cannot drop a neighbour on the sphere.
      const float bound =
          reach == kInf ? kInf : (reach + (q - prev).norm()) * (1 + 1e-5f) + 1e-6f;
      reach = local_surface(tree_, point, q, k, options.gicp_epsilon,
                            options.normals ? &normals_[i] : nullptr,
                            nullptr, bound,
                            options.neighborhoods ? &neighborhoods_[i * k] : nullptr,
                            options.covariances ? &gicp_axes_[i] : nullptr);
      prev = q;
    }
  });
}

Eigen::Matrix3d PreparedCloud3D::covariance(std::size_t i) const {
  ROVE_CHECK_MSG(has_covariances(), "the cloud was prepared without covariances");
  ROVE_CHECK_LT(i, size());
  const Eigen::Vector3d& v = gicp_axes_[i];
  if (v.isZero(0)) return Eigen::Matrix3d::Identity();
  // The expression local_surface_3d evaluates, to the last bit.
  return Eigen::Matrix3d::Identity() - (1.0 - options_.gicp_epsilon) * v * v.transpose();
}

namespace {

/// local_surface_3d with the neighbours' coordinates read through `point`
/// (source index → coordinates).
template <typename PointOf>
float local_surface(const KdTree3f& tree, const PointOf& point, const Eigen::Vector3f& query,
                    std::size_t k, double gicp_epsilon, Eigen::Vector3f* normal,
                    Eigen::Matrix3d* covariance, float bound, Neighbor<float>* neighbors,
                    Eigen::Vector3d* axis) {
  constexpr std::size_t kMaxK = 64;
  Neighbor<float> buf[kMaxK];
  std::vector<Neighbor<float>> big;
  std::span<Neighbor<float>> nn(buf, std::min(k, kMaxK));
  if (neighbors) {
    nn = std::span<Neighbor<float>>(neighbors, k);
  } else if (k > kMaxK) {
    big.resize(k);
    nn = big;
  }
  std::size_t m = std::isfinite(bound) ? tree.knn(query, k, nn, bound) : tree.knn(query, k, nn);
  if (m < std::min(k, tree.size())) m = tree.knn(query, k, nn);  // the bound was too tight
  if (m < 3) {
    if (normal) normal->setZero();
    if (covariance) *covariance = Eigen::Matrix3d::Identity();
    if (axis) axis->setZero();
    return std::numeric_limits<float>::infinity();
  }
  const float reach = std::sqrt(nn[m - 1].sq_distance);
  // Moments about the query point: the sums stay small, so the covariance
  // keeps its precision far from the origin.
  const double ox = query.x(), oy = query.y(), oz = query.z();
  double sx = 0, sy = 0, sz = 0, sxx = 0, sxy = 0, sxz = 0, syy = 0, syz = 0, szz = 0;
  for (std::size_t j = 0; j < m; ++j) {
    const Eigen::Vector3f& pf = point(nn[j].index);
    const double x = static_cast<double>(pf.x()) - ox;
    const double y = static_cast<double>(pf.y()) - oy;
    const double z = static_cast<double>(pf.z()) - oz;
    sx += x;
    sy += y;
    sz += z;
    sxx += x * x;
    sxy += x * y;
    sxz += x * z;
    syy += y * y;
    syz += y * z;
    szz += z * z;
  }
  const double inv = 1.0 / static_cast<double>(m);
  const double mx = sx * inv, my = sy * inv, mz = sz * inv;
  Eigen::Matrix3d C;
  C(0, 0) = sxx * inv - mx * mx;
  C(0, 1) = C(1, 0) = sxy * inv - mx * my;
  C(0, 2) = C(2, 0) = sxz * inv - mx * mz;
  C(1, 1) = syy * inv - my * my;
  C(1, 2) = C(2, 1) = syz * inv - my * mz;
  C(2, 2) = szz * inv - mz * mz;
  double lambda = 0;
  Eigen::Vector3d v;
  const bool flat = !smallest_eigenpair_psd(C, lambda, v);
  if (normal) *normal = flat ? Eigen::Vector3f::Zero() : Eigen::Vector3f(v.cast<float>());
  if (axis) *axis = flat ? Eigen::Vector3d::Zero() : v;
  if (covariance) {
    // V·diag(ε, 1, 1)·Vᵀ = I − (1 − ε)·v₁v₁ᵀ (PreparedCloud3D::covariance
    // evaluates the same expression).
    *covariance = flat ? Eigen::Matrix3d::Identity()
                       : Eigen::Matrix3d(Eigen::Matrix3d::Identity() - (1.0 - gicp_epsilon) * v * v.transpose());
  }
  return reach;
}

}  // namespace

bool smallest_eigenpair_psd(const Eigen::Matrix3d& C, double& eigenvalue, Eigen::Vector3d& eigenvector) {
  if (!C.allFinite()) return false;
  // On C / scale: entries at most 1, and tr >= 1 (a PSD matrix's largest
  // entry is on its diagonal).
  const double scale = C.cwiseAbs().maxCoeff();
  if (!(scale > 0)) return false;
  const double inv = 1 / scale;
  const double xx = C(0, 0) * inv, xy = C(0, 1) * inv, xz = C(0, 2) * inv;
  const double yy = C(1, 1) * inv, yz = C(1, 2) * inv, zz = C(2, 2) * inv;
  const double tr = xx + yy + zz;
  const double m2 = xx * yy + xx * zz + yy * zz - xy * xy - xz * xz - yz * yz;
  const double det = xx * (yy * zz - yz * yz) - xy * (xy * zz - yz * xz) + xz * (xy * yz - yy * xz);
  // λ₁ is at most the smallest diagonal entry (a Rayleigh quotient).
  const double ceiling = std::min({xx, yy, zz});
  // Start at det/m₂ = λ₁λ₂λ₃/(λ₁λ₂ + λ₁λ₃ + λ₂λ₃) <= λ₁: below the root
  // as Newton needs, and next to it when λ₁ ≪ λ₂ (a surface), where one or
  // two steps then finish.
  // m₂ at rounding level means rank one (λ₁ = λ₂ = 0) and det/m₂ would be
  // noise over noise; a start the rounding put above the root starts over
  // from 0.
  double lambda = 0;
  if (det > 0 && m2 > 1e-12 * tr * tr) {
    const double start = std::min(det / m2, ceiling);
    if (((start - tr) * start + m2) * start - det < 0) lambda = start;
  }
  // Quadratic convergence on a simple root; at a double root (λ₁ = λ₂,
  // where the eigenvector is any vector of a plane) it halves the gap per
  // step, so the cap of 64 still reaches double precision. Where q' is
  // down to rounding (1e-12 of tr², its scale), λ is within ~1e-12 of a
  // multiple root and a Newton step would divide noise by noise: stop.
  // On a simple root the error after a step s is O(s²/gap), so once a step
  // is below 1e-10·tr the next would change λ by ~1e-20 of tr²/gap: stop
  // there (the eigenvalue returned is the Rayleigh quotient below anyway).
  // That saved one step in four on scan neighbourhoods.
  for (int it = 0; it < 64; ++it) {
    const double q = ((lambda - tr) * lambda + m2) * lambda - det;
    const double dq = (3 * lambda - 2 * tr) * lambda + m2;
    if (!(q < 0) || !(dq > 1e-12 * tr * tr)) break;
    const double step = -q / dq;
    const double next = std::min(lambda + step, ceiling);
    if (!(next > lambda)) break;
    const bool small = !(next - lambda > 1e-10 * tr);
    lambda = next;
    if (small) break;
  }
  const Eigen::Vector3d r0(xx - lambda, xy, xz), r1(xy, yy - lambda, yz), r2(xz, yz, zz - lambda);
  const Eigen::Vector3d c[3] = {r0.cross(r1), r0.cross(r2), r1.cross(r2)};
  int best = 0;
  double best_sq = c[0].squaredNorm();
  for (int i = 1; i < 3; ++i)
    if (c[i].squaredNorm() > best_sq) {
      best = i;
      best_sq = c[i].squaredNorm();
    }
  const Eigen::Vector3d* r[3] = {&r0, &r1, &r2};
  int top = 0;
  for (int i = 1; i < 3; ++i)
    if (r[i]->squaredNorm() > r[top]->squaredNorm()) top = i;
  const double row_sq = r[top]->squaredNorm();
  // A cross product carries rounding of ~1e-16·|row|²; far above that
  // (1e-10·|row|²) its direction is good to 1e-6. Below it, λ₁ and λ₂
  // agree to 1e-10 (relative) and the eigenvector is any vector of their
  // plane.
  if (best_sq > 1e-20 * row_sq * row_sq) {
    eigenvector = c[best] / std::sqrt(best_sq);
  } else {
    // Rank one or zero: the eigenspace is a plane (orthogonal to the
    // largest row) or everything.
    const Eigen::Vector3d& row = *r[top];
    if (row_sq > 1e-24) {
      Eigen::Index axis = 0;
      row.cwiseAbs().minCoeff(&axis);
      eigenvector = row.cross(Eigen::Vector3d::Unit(axis)).normalized();
    } else {
      eigenvector = Eigen::Vector3d::UnitX();
    }
  }
  // The Rayleigh quotient: exact for an exact eigenvector, and accurate
  // where λ, a multiple root of the cubic, is found only to the square (or
  // cube) root of the rounding.
  const Eigen::Vector3d& v = eigenvector;
  const double rayleigh = xx * v.x() * v.x() + yy * v.y() * v.y() + zz * v.z() * v.z() +
                          2 * (xy * v.x() * v.y() + xz * v.x() * v.z() + yz * v.y() * v.z());
  eigenvalue = std::max(rayleigh, 0.0) * scale;
  return true;
}

void local_surface_3d(const KdTree3f& tree, const Eigen::Vector3f& query, std::size_t k,
                      double gicp_epsilon, Eigen::Vector3f* normal, Eigen::Matrix3d* covariance) {
  local_surface(tree, [&](std::uint32_t i) { return tree.indexed_point(i); }, query, k,
                gicp_epsilon, normal, covariance, std::numeric_limits<float>::infinity());
}

}  // namespace rove
