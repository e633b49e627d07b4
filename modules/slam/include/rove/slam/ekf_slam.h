#pragma once
/// \file
/// EKF landmark SLAM with range-bearing sensors (MRPT's CRangeBearingKFSLAM2D
/// and CRangeBearingKFSLAM): a robot pose in SE(2) or SE(3) and point
/// landmarks in the plane or in space, observed as (range, yaw) or (range,
/// yaw, pitch) from a sensor mounted on the robot.
///
/// State: the robot pose X = T_world_robot and the landmark positions
/// p_world. The covariance is over (δ, p) with δ the robot's right tangent,
/// X_true = X·exp(δ) (docs/conventions.md), so a 3D robot has 6 degrees of
/// freedom and no quaternion normalization (MRPT keeps a 7-vector).
///
/// Prediction: X ← X·U with U the odometry increment and Σ_U its
/// covariance over U's right tangent: δ' = Adj(U⁻¹)·δ + ε, so only the
/// robot's rows and columns change, O(n) for n state components. While the
/// map is empty only the mean moves: the robot's pose at its first
/// landmarks fixes the map frame (MRPT skips the prediction then).
///
/// Update: the sensor sees p_s = (X·T_robot_sensor)⁻¹·p_world and measures
/// r = ‖p_s‖, yaw = atan2(y, x), pitch = −atan2(z, √(x²+y²)) (positive pitch
/// below the XY plane, MRPT's sphericalCoordinates). Each reading's
/// Jacobian is nonzero only in the robot's and its landmark's columns, so
/// P·Hᵀ costs O(n·m) for m measured values; the covariance update P −=
/// (PHᵀ)·S⁻¹·(PHᵀ)ᵀ is a symmetric rank-m update (O(n²·m), the EKF's
/// unavoidable cost), kept symmetric by construction.
///
/// New landmarks: p_world = X·T_robot_sensor·p_s(z), initialized with the
/// Jacobians G_δ, G_z of that map: P_ll = G_δ P_δδ G_δᵀ + G_z R G_zᵀ and
/// P_l· = G_δ P_δ· (Davison's initialization; Dissanayake et al., IEEE
/// T-RA 17(3), 2001), added after the frame's update as MRPT.
///
/// Pairing: a reading with a landmark ID is paired by it (known-ID mode);
/// readings without one go to data_association.h with the joint innovation
/// covariance of the landmarks that can be compatible.
///
/// Thread-safety: an EkfSlam is not safe for concurrent use.

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include <Eigen/Core>

#include "rove/math/se2.h"
#include "rove/math/se3.h"
#include "rove/slam/data_association.h"
#include "rove/slam/ekf_slam_options.h"

namespace rove {

/// Sizes and types of EKF-SLAM in `Dim` dimensions (2 or 3).
template <int Dim>
struct EkfSlamTraits;

/// Planar robot (x, y, heading), planar landmarks, (range, yaw) readings.
template <>
struct EkfSlamTraits<2> {
  using Pose = SE2d;                       ///< T_world_robot
  static constexpr int kPoseDof = 3;       ///< (ρx, ρy, θ)
  static constexpr int kLandmarkDim = 2;   ///< (x, y) m
  static constexpr int kReadingDim = 2;    ///< (range m, yaw rad)
};

/// 6-DoF robot, 3D point landmarks, (range, yaw, pitch) readings.
template <>
struct EkfSlamTraits<3> {
  using Pose = SE3d;                       ///< T_world_robot
  static constexpr int kPoseDof = 6;       ///< (ρ, ω)
  static constexpr int kLandmarkDim = 3;   ///< (x, y, z) m
  static constexpr int kReadingDim = 3;    ///< (range m, yaw rad, pitch rad)
};

/// An odometry increment U = T_robot(k−1)_robot(k) with its covariance
/// over U's right tangent.
template <int Dim>
struct EkfSlamOdometry {
  /// Pose type of the dimension.
  using Pose = typename EkfSlamTraits<Dim>::Pose;
  /// Covariance type over the pose's tangent.
  using Covariance = Eigen::Matrix<double, EkfSlamTraits<Dim>::kPoseDof,
                                   EkfSlamTraits<Dim>::kPoseDof>;
  /// The increment.
  Pose increment;
  /// Its covariance (symmetric PSD).
  Covariance covariance = Covariance::Zero();
};

/// One range-bearing reading.
template <int Dim>
struct EkfSlamReading {
  /// The landmark's ID, or −1 if the sensor does not identify it.
  std::int64_t id = -1;
  /// (range m, yaw rad[, pitch rad]).
  Eigen::Matrix<double, EkfSlamTraits<Dim>::kReadingDim, 1> z;
};

/// The readings of one sensor at one step.
template <int Dim>
struct EkfSlamFrame {
  /// Where the sensor sits on the robot, T_robot_sensor.
  typename EkfSlamTraits<Dim>::Pose T_robot_sensor;
  /// The readings.
  std::vector<EkfSlamReading<Dim>> readings;
};

/// What happened to one reading.
enum class ReadingOutcome : std::uint8_t {
  /// Paired with a mapped landmark by its ID.
  PairedById,
  /// Paired with a mapped landmark by data association.
  Associated,
  /// Started a new landmark.
  NewLandmark,
  /// Not used: range ≤ 0 (no direction) or an ID repeated within the frame.
  Skipped,
};

/// How an update ended.
enum class EkfSlamTermination : std::uint8_t {
  /// The paired readings updated the filter (or there were none to pair).
  Updated,
  /// The innovation covariance was not positive definite: the update was
  /// skipped (new landmarks were still added).
  NotPositiveDefinite,
};

/// What one step did.
struct EkfSlamStepResult {
  /// How the update ended.
  EkfSlamTermination termination = EkfSlamTermination::Updated;
  /// One line: readings, pairings, new landmarks, NIS.
  std::string message;
  /// Per reading of the frame: what happened to it.
  std::vector<ReadingOutcome> outcome;
  /// Per reading: the landmark index it was paired with or started, −1 if skipped.
  std::vector<int> landmark;
  /// Counts of the outcomes.
  std::size_t by_id = 0, associated = 0, created = 0, skipped = 0;
  /// Normalized innovation squared of the paired readings at the prior
  /// (νᵀS⁻¹ν; the sum over the sequential updates) and its degrees of freedom.
  double nis = 0.0;
  /// Degrees of freedom of nis: the number of paired measured values.
  std::size_t nis_dof = 0;
  /// The data association of the readings without ID (empty if none ran).
  std::optional<DataAssociationResult> association;
};

/// EKF-SLAM in `Dim` dimensions (2 or 3); see the file comment.
template <int Dim>
class EkfSlam {
 public:
  /// Traits of the dimension.
  using Traits = EkfSlamTraits<Dim>;
  /// T_world_robot.
  using Pose = typename Traits::Pose;
  static constexpr int kD = Traits::kPoseDof;       ///< robot degrees of freedom
  static constexpr int kL = Traits::kLandmarkDim;   ///< landmark dimension
  static constexpr int kM = Traits::kReadingDim;    ///< reading dimension
  /// Robot covariance type.
  using PoseCovariance = Eigen::Matrix<double, kD, kD>;
  /// Landmark position type.
  using Point = Eigen::Matrix<double, kL, 1>;
  /// Landmark covariance type.
  using PointCovariance = Eigen::Matrix<double, kL, kL>;

  /// Robot at the identity with zero covariance (the map frame is the
  /// robot's first pose), no landmarks. Throws InvalidArgument for invalid
  /// options (EkfSlamOptions::check).
  explicit EkfSlam(EkfSlamOptions options);

  /// Prediction with an odometry increment, or with options' no-odometry
  /// noise when `odometry` is empty or force_ignore_odometry is set.
  /// Precondition (InvalidArgument): finite covariance.
  void predict(const std::optional<EkfSlamOdometry<Dim>>& odometry);
  /// Update with a frame's readings, then new landmarks for the unpaired
  /// ones. Preconditions (InvalidArgument): finite readings.
  EkfSlamStepResult update(const EkfSlamFrame<Dim>& frame);
  /// predict() then update().
  EkfSlamStepResult step(const std::optional<EkfSlamOdometry<Dim>>& odometry,
                         const EkfSlamFrame<Dim>& frame);

  /// The options.
  const EkfSlamOptions& options() const noexcept { return options_; }
  /// The robot pose mean, T_world_robot.
  const Pose& pose() const noexcept { return pose_; }
  /// The robot pose covariance over its right tangent.
  PoseCovariance pose_covariance() const;
  /// Number of landmarks.
  std::size_t landmark_count() const noexcept { return ids_.size(); }
  /// Landmark i's position mean, world frame (m). Precondition: i < count.
  Point landmark(std::size_t i) const;
  /// Landmark i's position covariance (m²). Precondition: i < count.
  PointCovariance landmark_covariance(std::size_t i) const;
  /// Landmark i's ID (the reading's that started it; −1 if none).
  std::int64_t landmark_id(std::size_t i) const;
  /// Times landmark i was observed (the reading that started it included).
  std::size_t landmark_observations(std::size_t i) const;
  /// The full covariance over (δ, landmarks…), n × n.
  Eigen::MatrixXd covariance() const;
  /// State size n = kD + kL · landmark_count().
  Eigen::Index state_size() const noexcept { return n_; }
  /// The predicted reading of landmark i from the current mean with its
  /// innovation covariance S = H P Hᵀ + R, for a sensor at T_robot_sensor.
  /// False if the landmark is at the sensor's origin or (3D) on its z axis,
  /// where the bearing has no derivative.
  bool predict_reading(std::size_t i, const Pose& T_robot_sensor,
                       Eigen::Matrix<double, kM, 1>* z,
                       Eigen::Matrix<double, kM, kM>* S) const;

 private:
  struct Linearization;
  using ReadingCovariance = Eigen::Matrix<double, kM, kM>;

  bool linearize(std::size_t i, const Pose& T_rs, Linearization& lin) const;
  void pair_by_id(const EkfSlamFrame<Dim>& frame, EkfSlamStepResult& r,
                  std::vector<std::pair<int, int>>& pairs) const;
  void pair_by_association(const EkfSlamFrame<Dim>& frame, EkfSlamStepResult& r,
                           std::vector<std::pair<int, int>>& pairs) const;
  bool kalman_update(const EkfSlamFrame<Dim>& frame, const std::vector<std::pair<int, int>>& pairs,
                     double& nis);
  void add_landmark(const EkfSlamReading<Dim>& reading, const Pose& T_rs);
  void reserve(Eigen::Index n);
  ReadingCovariance reading_noise() const;

  EkfSlamOptions options_;
  Pose pose_;
  Eigen::Index n_ = kD;
  Eigen::VectorXd landmarks_;    // capacity-sized, first n_ − kD used
  Eigen::MatrixXd P_;            // capacity-sized, top-left n_ × n_ used
  std::vector<std::int64_t> ids_;
  std::vector<std::size_t> seen_;
  std::unordered_map<std::int64_t, int> index_of_id_;
  double ic_chi2_ = 0.0;  // individual-compatibility χ² threshold for kM values
};

extern template class EkfSlam<2>;
extern template class EkfSlam<3>;

/// Planar EKF-SLAM (MRPT's CRangeBearingKFSLAM2D).
using EkfSlam2D = EkfSlam<2>;
/// 6-DoF EKF-SLAM (MRPT's CRangeBearingKFSLAM).
using EkfSlam3D = EkfSlam<3>;

/// "paired-by-id", "associated", "new-landmark", "skipped".
std::string_view to_string(ReadingOutcome outcome) noexcept;

}  // namespace rove
