#pragma once
/// \file
/// PreparedCloud3D: a 3D point set with what 3D registration needs beside
/// the coordinates — a KD-tree, and on request unit normals (point-to-plane
/// ICP, degeneracy checks) and regularized covariances (GICP). Build it once
/// per cloud; a target can serve many registrations (a map), and a source
/// can be registered against many targets.
///
/// Normals and covariances come from the k nearest neighbours of each point
/// (the point included): the sample covariance C, eigen-decomposed as
/// C = Σ λᵢ vᵢvᵢᵀ (λ₁ ≤ λ₂ ≤ λ₃). The normal is v₁. The GICP covariance is
/// the plane-to-plane regularization of Segal, Haehnel, Thrun,
/// "Generalized-ICP", RSS 2009, Sec. III.B: eigenvalues replaced by
/// (ε, 1, 1), ε = 1e-3 (as PCL's GICP and small_gicp), so every point is a
/// thin disc of unit radius along its local surface.
///
/// Thread-safety: immutable after construction.

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "rove/maps/kdtree.h"
#include "rove/maps/point_cloud_concept.h"

namespace rove {

/// What PreparedCloud3D computes.
struct PrepareOptions {
  /// Compute unit normals. Default false.
  bool normals = false;
  /// Compute GICP covariances. Default false.
  bool covariances = false;
  /// Neighbours (point included) for normals and covariances, ≥ 3.
  /// Default 20 (PCL GICP's k_correspondences).
  std::size_t neighbors = 20;
  /// Smallest regularized eigenvalue ε of the GICP covariances, in (0, 1].
  /// Default 1e-3.
  double gicp_epsilon = 1e-3;
  /// Threads for the neighbour searches; results do not depend on it. 1 to
  /// kMaxThreads (rove/core/parallel.h), 0 for all hardware threads; other
  /// values are an InvalidArgument. Default 1.
  int num_threads = 1;
  /// Keep the neighbourhoods the normals or covariances come from
  /// (neighborhoods(), 8·k bytes per point), which the pairing of a target
  /// walks. A cloud that will only be a source never needs them: false
  /// saves that memory and about 3 % of a GICP run. Default true.
  bool neighborhoods = true;
};

/// A 3D point set prepared for registration. See the file comment.
class PreparedCloud3D {
 public:
  /// An empty cloud.
  PreparedCloud3D();
  /// Keeps the finite points of `points` (meters) and computes what
  /// `options` asks. Preconditions (InvalidArgument): options valid, fewer
  /// than 2^32 points.
  explicit PreparedCloud3D(std::vector<Eigen::Vector3f> points, const PrepareOptions& options = {});
  /// From any PointCloudLike 3D cloud (coordinates converted to float).
  template <PointCloudLike C>
    requires(cloud_dim_v<C> == 3)
  static PreparedCloud3D from_cloud(const C& cloud, const PrepareOptions& options = {}) {
    std::vector<Eigen::Vector3f> pts;
    const std::size_t n = point_count(cloud);
    pts.reserve(n);
    for (std::size_t i = 0; i < n; ++i) pts.push_back(point_at(cloud, i).template cast<float>());
    return PreparedCloud3D(std::move(pts), options);
  }

  PreparedCloud3D(PreparedCloud3D&&) noexcept;
  PreparedCloud3D& operator=(PreparedCloud3D&&) noexcept;
  ~PreparedCloud3D();

  /// Number of (finite) points.
  std::size_t size() const noexcept { return points_.size(); }
  /// True when there is no point.
  bool empty() const noexcept { return points_.empty(); }
  /// The points, meters.
  const std::vector<Eigen::Vector3f>& points() const noexcept { return points_; }
  /// KD-tree over points() (indices refer to points()).
  const KdTree3f& tree() const noexcept { return tree_; }
  /// Unit normals (empty unless computed). A point whose neighbourhood has
  /// no extent gets (0, 0, 0).
  std::span<const Eigen::Vector3f> normals() const noexcept { return normals_; }
  bool has_normals() const noexcept { return !normals_.empty(); }
  /// True when the GICP covariances were computed.
  bool has_covariances() const noexcept { return !gicp_axes_.empty(); }
  /// The GICP covariance of point i, m²: I − (1 − ε)·v₁v₁ᵀ with v₁ =
  /// gicp_axes()[i] and ε = options().gicp_epsilon, or I where the
  /// neighbourhood has no extent. Computed from the axis on each call (the
  /// cloud stores 3 numbers per point, not 9).
  /// Preconditions: has_covariances(), i < size().
  Eigen::Matrix3d covariance(std::size_t i) const;
  /// The axis of each GICP covariance (empty unless computed): the unit
  /// normal v₁ of the neighbourhood, or zero where the covariance is I (a
  /// neighbourhood without extent).
  std::span<const Eigen::Vector3d> gicp_axes() const noexcept { return gicp_axes_; }
  /// The neighbourhoods the normals or covariances were computed from
  /// (empty when neither was, or when options().neighborhoods is false):
  /// row i, neighbors_per_point() entries from neighborhoods()[i·k], holds
  /// the k nearest points of point i (itself included) as indices into
  /// points() with their squared distances (m², float, as the tree computes
  /// them), nearest first. No point outside row i lies nearer to point i
  /// than its last entry.
  std::span<const Neighbor<float>> neighborhoods() const noexcept { return neighborhoods_; }
  /// Entries per row of neighborhoods(): min(options().neighbors, size()),
  /// or 0 when none are kept.
  std::size_t neighbors_per_point() const noexcept { return neighbors_per_point_; }
  bool has_neighborhoods() const noexcept { return !neighborhoods_.empty(); }
  /// The options it was prepared with.
  const PrepareOptions& options() const noexcept { return options_; }

 private:
  std::vector<Eigen::Vector3f> points_;
  std::vector<Eigen::Vector3f> normals_;
  std::vector<Eigen::Vector3d> gicp_axes_;
  std::vector<Neighbor<float>> neighborhoods_;
  std::size_t neighbors_per_point_ = 0;
  KdTree3f tree_;
  PrepareOptions options_;
};

/// The smallest eigenvalue of a symmetric positive semi-definite 3×3
/// matrix and a unit eigenvector of it; false (outputs untouched) when C is
/// zero or not finite. The normal and GICP axis of a neighbourhood.
///
/// Without trigonometry: Newton's method on the characteristic cubic
/// q(λ) = λ³ − tr·λ² + m₂·λ − det from λ = 0, which lies below the
/// smallest root; all roots are real and q is increasing and concave below
/// the smallest, so the iterates climb to it without overshooting. The
/// eigenvector is the largest cross product of two rows of C − λI (they
/// span its orthogonal complement); when λ is a double root, any unit
/// vector orthogonal to the remaining row, and (1, 0, 0) for a multiple of
/// I. The eigenvalue is the Rayleigh quotient of that vector. Matches
/// Eigen's closed form to ~1e-9 on separated eigenvalues, without its
/// atan2, sin and cos.
bool smallest_eigenpair_psd(const Eigen::Matrix3d& C, double& eigenvalue, Eigen::Vector3d& eigenvector);

/// smallest_eigenpair_psd of every matrix of C: found[i] is its return
/// value, and eigenvalues[i] / eigenvectors[i] its outputs (untouched
/// where found[i] is false). The same results bit for bit, in about a
/// third less time on scan neighbourhoods (83 vs 115-130 ns per matrix):
/// the Newton steps of four matrices are interleaved, so that their
/// divisions overlap instead of waiting on each other. Where AVX2 runs
/// (rove/core/cpu.h), four matrices at a time in vector lanes, again the
/// same results (56 ns per matrix).
/// Precondition (InvalidArgument): all four spans have the same size.
void smallest_eigenpairs_psd(std::span<const Eigen::Matrix3d> C, std::span<double> eigenvalues,
                             std::span<Eigen::Vector3d> eigenvectors, std::span<bool> found);

/// Normal (unit, or zero when the neighbourhood has no extent) and GICP
/// covariance of the neighbourhood of `query` among the k nearest points of
/// `tree`; either output may be null.
void local_surface_3d(const KdTree3f& tree, const Eigen::Vector3f& query, std::size_t k,
                      double gicp_epsilon, Eigen::Vector3f* normal, Eigen::Matrix3d* covariance);

}  // namespace rove
