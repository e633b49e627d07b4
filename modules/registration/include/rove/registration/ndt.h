#pragma once
/// \file
/// The Normal Distributions Transform (NDT) in 3D and 2D, with the semantics
/// of PCL 1.13's pcl::NormalDistributionsTransform (Magnusson, "The
/// three-dimensional normal-distributions transform", PhD thesis, Örebro
/// 2009, Ch. 6):
///  - the target is cut into cubic (square) cells of side `resolution`; a
///    cell with at least min_points_per_voxel points becomes a Gaussian
///    (sample mean and covariance, eigenvalues below
///    min_covariance_eigenvalue_ratio·λmax raised to it, as PCL's
///    VoxelGridCovariance);
///  - the score of a pose is Σ over source points and over every cell whose
///    mean is within `resolution` of the transformed point of
///    −d₁·exp(−d₂/2 · x′ᵀΣ⁻¹x′) (eq. 6.9, with d₁, d₂ from the outlier ratio,
///    eq. 6.8), maximized by Newton's method with analytic gradient and
///    Hessian (eq. 6.12-6.13, 6.17-6.21);
///  - each Newton direction is searched with the Moré–Thuente line search
///    ("Line search algorithms with guaranteed sufficient decrease", ACM
///    TOMS 1994), step length at most step_size.
/// By default (NdtCompat::None) the Newton steps perturb the pose locally,
/// R ← Exp(ω)·R, t ← t + ρ (rotation about the sensor's position with the
/// target's axes; 2D: θ ← θ + ω), with the exact gradient and Hessian of the
/// score: no Euler angles, so no gimbal lock; the run converges when the score has a
/// maximum at the estimate (its Hessian is negative definite) and the full
/// Newton step to it is within translation_tolerance and rotation_tolerance;
/// it ends MaxIterations at the cap and Stalled when no step along the
/// Newton direction raises the score. NdtCompat::Pcl reproduces PCL instead
/// (ndt_pcl.cpp): its (x, y, z, roll, pitch, yaw) parameters with
/// R = Rx·Ry·Rz (2D: x, y, phi), its rule (a taken step's translation² ≤
/// transformation_epsilon: with PCL's defaults, 0.1 m² and steps of at most
/// 0.1, it holds after the first step wherever that ends, so it says nothing
/// about the optimum), its shortest line-search step transformation_epsilon/2
/// and its steps taken even when they lower the score.
///
/// Uncertainty of the result, in either mode: information −H, H the score
/// Hessian at the result, and covariance (−H)⁻¹, over the right tangent
/// (ρ, ω) (docs/conventions.md; to_pose3_gaussian in rove/poses/
/// lie_conversion.h gives MRPT's (x, y, z, yaw, pitch, roll) form). The NDT
/// score is a likelihood only up to the scale of d₁, d₂, so read it as a
/// shape, not as calibrated metres.

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "rove/maps/kdtree.h"
#include "rove/math/se2.h"
#include "rove/math/se3.h"
#include "rove/registration/termination.h"

namespace rove {

/// How the target cells are built (PCL's VoxelGridCovariance settings).
struct NdtGridOptions {
  /// Cell side, meters, > 0. Default 1.0 (PCL).
  double resolution = 1.0;
  /// Fewest points for a cell to count, ≥ 3. Default 6 (PCL).
  int min_points_per_voxel = 6;
  /// Eigenvalues below this fraction of the largest are raised to it, in
  /// (0, 1]. Default 0.01 (PCL).
  double min_covariance_eigenvalue_ratio = 0.01;
};

/// One Gaussian cell of an NDT grid.
template <int Dim>
struct NdtCell {
  Eigen::Matrix<double, Dim, 1> mean;          ///< meters
  Eigen::Matrix<double, Dim, Dim> inverse_covariance;  ///< m⁻²
  /// Eigenvector of the smallest eigenvalue; zero for a 3D cell whose points
  /// are (nearly) collinear, which has no defined surface normal.
  Eigen::Matrix<double, Dim, 1> normal;
  int points = 0;                              ///< points in the cell
};

/// The target of NDT: Gaussian cells and a KD-tree over their means.
/// Immutable after construction; thread-safe for concurrent registrations.
template <int Dim>
class NdtGrid {
 public:
  using Point = Eigen::Matrix<double, Dim, 1>;
  /// An empty grid.
  NdtGrid();
  /// Builds the cells from the finite points of `points` (meters).
  /// Preconditions (InvalidArgument): options valid; the grid index range
  /// fits in 63 bits.
  NdtGrid(std::span<const Eigen::Matrix<float, Dim, 1>> points, const NdtGridOptions& options = {});
  NdtGrid(NdtGrid&&) noexcept;
  NdtGrid& operator=(NdtGrid&&) noexcept;
  ~NdtGrid();

  /// The cells (those with enough points and a valid covariance).
  const std::vector<NdtCell<Dim>>& cells() const noexcept { return cells_; }
  /// True when there is no cell.
  bool empty() const noexcept { return cells_.empty(); }
  /// KD-tree over the cell means (indices refer to cells()).
  const KdTree<Dim, double>& tree() const noexcept { return tree_; }

  /// Most cells cells_near can report: 3^Dim.
  static constexpr std::size_t kMaxNear = Dim == 3 ? 27 : 9;
  /// The cells whose mean is within `resolution` of x (distance ≤
  /// resolution; the set tree().radius(x, resolution) returns, with the same
  /// squared distances), written to the front of `out` in a deterministic
  /// order; returns how many. Reads the 3^Dim cells around x in a dense
  /// index when the grid's extent allows it (≤ 2^22 cells, or 64 per
  /// Gaussian cell), else searches the KD-tree.
  std::size_t cells_near(const Point& x, std::span<Neighbor<double>, kMaxNear> out) const;
  /// The cell whose mean is nearest to x within `resolution` (inclusive;
  /// among equally near means, the lowest index); nullopt when there is none
  /// or x is not finite. Same index as cells_near.
  std::optional<Neighbor<double>> nearest_cell(const Point& x) const;
  /// The options it was built with.
  const NdtGridOptions& options() const noexcept { return options_; }

 private:
  std::vector<NdtCell<Dim>> cells_;
  KdTree<Dim, double> tree_;
  void build_lookup();
  // The lookup cell of x (row-major index into lookup_start_ − 1), or −1
  // when x is outside the index or not finite.
  std::int64_t lookup_index(const Point& x) const;
  // Dense index over the bounding box of the means' own cells
  // (floor(mean / resolution)) grown by one cell on every side, CSR: the
  // cells whose mean lies in the 3^Dim lookup cells around lookup cell l are
  // lookup_cells_[lookup_start_[l] .. lookup_start_[l + 1]), in row-major
  // order of their own lookup cell, then by index. Empty when the box is too
  // large; cells_near then uses the tree. lookup_means_[c] = cells_[c].mean.
  Eigen::Matrix<std::int64_t, Dim, 1> lookup_min_ = Eigen::Matrix<std::int64_t, Dim, 1>::Zero();
  Eigen::Matrix<std::int64_t, Dim, 1> lookup_size_ = Eigen::Matrix<std::int64_t, Dim, 1>::Zero();
  std::vector<std::uint32_t> lookup_start_;
  std::vector<std::uint32_t> lookup_cells_;
  std::vector<Point> lookup_means_;
  NdtGridOptions options_;
};

using NdtGrid3D = NdtGrid<3>;
using NdtGrid2D = NdtGrid<2>;
extern template class NdtGrid<2>;
extern template class NdtGrid<3>;

/// Which NDT runs: rove's, or PCL's for parity with it (file comment).
enum class NdtCompat {
  /// Newton steps on a local perturbation of the pose; converged when the
  /// score has a maximum at the estimate and the full Newton step to it
  /// (before the step_size cap) is within translation_tolerance and
  /// rotation_tolerance; a step that does not raise the score is not taken.
  None,
  /// PCL 1.13's NormalDistributionsTransform: Euler parameters (x, y, z,
  /// roll, pitch, yaw), R = Rx·Ry·Rz (2D: x, y, phi); converged when a taken
  /// step's translation² ≤ transformation_epsilon (and, when set, cos(its
  /// rotation) ≥ transformation_rotation_epsilon) or a step is zero. Not a
  /// test of the optimum: with PCL's defaults it holds after the first step.
  Pcl,
};

/// Options of ndt_3d / ndt_2d.
struct NdtOptions {
  /// Largest Moré–Thuente step (in parameter units), > 0. Default 0.1 (PCL).
  double step_size = 0.1;
  /// rove's NDT or PCL's. Default None (rove's).
  NdtCompat compat = NdtCompat::None;
  /// None: the largest translation of the Newton step at a converged
  /// estimate, m, ≥ 0. Default 1e-3.
  double translation_tolerance = 1e-3;
  /// None: the largest rotation of the Newton step at a converged
  /// estimate, rad, ≥ 0. Default 1e-3 (0.057°).
  double rotation_tolerance = 1e-3;
  /// Pcl: converged when a step's translation² ≤ this (m²); also the
  /// line search's shortest step × 2, as in PCL. Unused by None. ≥ 0. Default 0.1 (PCL's NDT
  /// default; its tutorial uses 0.01).
  double transformation_epsilon = 0.1;
  /// Pcl: if > 0, convergence also needs cos(step rotation) ≥ this. In
  /// [0, 1]. Default 0.
  double transformation_rotation_epsilon = 0.0;
  /// Iteration cap, ≥ 1. Default 35 (PCL).
  int max_iterations = 35;
  /// Share of outliers in the score model, in (0, 1). Default 0.55 (PCL).
  double outlier_ratio = 0.55;
  /// Smallest accepted λmin/λmax of the normalized point-to-plane
  /// information of the matched cells (their normals at the source points);
  /// 0 disables. In [0, 1). Default 1e-3.
  double degeneracy_threshold = 1e-3;
  /// Threads; results are identical for any value. 1 to kMaxThreads
  /// (rove/core/parallel.h), 0 for all hardware threads. Default 1.
  int num_threads = 1;

  /// Throws InvalidArgument naming the first field out of range.
  void check() const;
};

/// Result of ndt_3d.
struct Ndt3dResult {
  /// Pose of the source in the target frame.
  SE3d T_target_source;
  /// Its covariance over the right tangent (ρ, ω): the inverse of
  /// `information` (zero when the run produced none).
  Eigen::Matrix<double, 6, 6> covariance = Eigen::Matrix<double, 6, 6>::Zero();
  /// Score / number of source points (PCL's getTransformationProbability).
  double transformation_probability = 0.0;
  /// Share of source points with at least one cell within `resolution`.
  double goodness = 0.0;
  /// Mean squared distance from each such point to its nearest cell mean, m².
  double fitness = 0.0;
  /// The cost the Newton iterations minimize at the result: the negated NDT
  /// score (Σ d₁·exp(...), Magnusson eq. 6.9; ≤ 0, lower is better).
  double final_cost = 0.0;
  /// Source points with at least one cell within `resolution` at the result.
  std::size_t correspondences = 0;
  /// −H, the negated score Hessian at the result, over the right tangent
  /// (ρ, ω); positive definite at a maximum.
  Eigen::Matrix<double, 6, 6> information = Eigen::Matrix<double, 6, 6>::Zero();
  /// Newton iterations (steps taken).
  int iterations = 0;
  /// λmin/λmax of the point-to-plane information of the matched cells.
  double conditioning = 0.0;
  /// Why the run stopped.
  RegistrationTermination termination = RegistrationTermination::InvalidInput;
  /// One line explaining the termination.
  std::string message;
  /// True only when termination is Converged (succeeded()).
  bool ok() const noexcept { return succeeded(termination); }
};

/// Result of ndt_2d (as Ndt3dResult, in 2D).
struct Ndt2dResult {
  SE2d T_target_source;
  /// Covariance over the right tangent (ρx, ρy, θ).
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  double transformation_probability = 0.0;
  double goodness = 0.0;
  double fitness = 0.0;
  double final_cost = 0.0;
  std::size_t correspondences = 0;
  /// −H over the right tangent (ρx, ρy, θ).
  Eigen::Matrix3d information = Eigen::Matrix3d::Zero();
  int iterations = 0;
  double conditioning = 0.0;
  RegistrationTermination termination = RegistrationTermination::InvalidInput;
  std::string message;
  bool ok() const noexcept { return succeeded(termination); }
};

/// 3D NDT of `source` (meters; non-finite points skipped) onto `target`
/// from `initial_T_target_source`. Preconditions (InvalidArgument):
/// options.check(). Empty inputs give
/// InvalidInput.
Ndt3dResult ndt_3d(const NdtGrid3D& target, std::span<const Eigen::Vector3f> source,
                   const SE3d& initial_T_target_source, const NdtOptions& options = {});

/// 2D NDT (cells are squares; the outlier constant uses the cell area).
Ndt2dResult ndt_2d(const NdtGrid2D& target, std::span<const Eigen::Vector2f> source,
                   const SE2d& initial_T_target_source, const NdtOptions& options = {});

}  // namespace rove
