#pragma once
/// \file
/// PointMap: a point cloud built from range observations with MRPT's
/// CPointsMap semantics (CSimplePointsMap; with the color channel
/// CColouredPointsMap; with the intensity channel CPointsMapXYZI), plus a
/// KD-tree rebuilt lazily after each change.
///
/// Insertion of a RangeScan2D at T_map_robot (MRPT's loadFromRangeScan):
/// the sensor pose is T_map_robot ⊕ T_robot_sensor; ray i with a valid range
/// becomes the point p_i. With min_dist_between_points > 0, p_i is kept only
/// if the previous ray was valid and p_i lies farther than that from the
/// last kept point; the first valid point and the last valid point of the
/// scan are always kept. With also_interpolate, between two consecutive kept
/// points whose distance d satisfies 2·min_dist <= d < max_dist_for_interpolate
/// and whose direction changes by less than 5°, round(d / (2·min_dist)) − 1
/// evenly spaced points are added. With is_planar_map, a scan whose sensor
/// pitch or roll exceeds horizontal_tolerance is not inserted.
/// The points' arithmetic is PointMapInsertionOptions::arithmetic: by
/// default p_i = R·(r_i cos θ_i, r_i sin θ_i, 0) + t in double, θ_i the
/// scan's own ray angle (RangeScan2D::ray_angle), rounded to float once;
/// Arithmetic::Mrpt gives MRPT 2.5.8's points to the bit (point_map_mrpt.cpp:
/// cos and sin rounded to float, the sensor pose rounded to float, the sums
/// in float).
///
/// Insertion of a RangeImage3D: pixels are visited in row-major order; a
/// valid pixel gives its projected point (RangeImage3D::project), an invalid
/// one the sensor origin if insert_invalid_points (MRPT's (0,0,0) points),
/// nothing otherwise; the same min-distance rule then applies. Colors (if
/// the map has them) come from the intensity image at the pixel the point
/// projects to in the intensity camera (gray images give gray colors).
///
/// With fuse_with_existing, each new point whose nearest map point (in XY,
/// as MRPT's determineMatching2D) is closer than min_dist_between_points is
/// averaged into that point instead of being added; with disable_deletion
/// false as well (2D scans only), map points that were not fused and lie
/// inside the polygon of the new scan (XY) are deleted as dynamic.
///
/// Thread-safety: const members may be called concurrently (the lazy
/// KD-tree build is guarded by a mutex); mutation needs exclusive access.

#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>

#include "rove/core/arithmetic.h"
#include "rove/core/config_section.h"
#include "rove/maps/kdtree.h"
#include "rove/maps/point_cloud.h"
#include "rove/obs/range_image_3d.h"
#include "rove/obs/range_scan_2d.h"
#include "rove/poses/pose3.h"

namespace rove {

/// MRPT's CPointsMap::TInsertionOptions, same defaults.
struct PointMapInsertionOptions {
  /// Meters; <= 0 disables the filter (`minDistBetweenLaserPoints`).
  float min_dist_between_points = 0.02f;
  /// load_scan(): false clears the map first (`addToExistingPointsMap`);
  /// insert() always adds, as MRPT's insertObservation does.
  bool add_to_existing = true;
  bool also_interpolate = false;             ///< `also_interpolate`
  bool disable_deletion = true;              ///< `disableDeletion`
  bool fuse_with_existing = false;           ///< `fuseWithExisting`
  bool is_planar_map = false;                ///< `isPlanarMap`
  /// Radians (`horizontalTolerance`; MRPT's default 0.05°).
  float horizontal_tolerance = static_cast<float>(0.05 * 3.14159265358979323846 / 180.0);
  float max_dist_for_interpolate = 2.0f;     ///< meters (`maxDistForInterpolatePoints`)
  bool insert_invalid_points = false;        ///< `insertInvalidPoints`
  /// `arithmetic` (rove's key: double | mrpt): how a 2D scan's points are
  /// computed (file comment). Double: in double, rounded once. Mrpt:
  /// MRPT's float arithmetic, so that the points are MRPT's to the bit.
  /// Default Double.
  Arithmetic arithmetic = Arithmetic::Double;

  /// MRPT's CPointsMap::TInsertionOptions keys present in `section`
  /// (`minDistBetweenLaserPoints`, `horizontalTolerance` in degrees,
  /// `addToExistingPointsMap`, `also_interpolate`, `disableDeletion`,
  /// `fuseWithExisting`, `isPlanarMap`, `maxDistForInterpolatePoints`,
  /// `insertInvalidPoints`, and rove's `arithmetic`) over MRPT's defaults.
  static PointMapInsertionOptions from_config(const ConfigSection& section);
};

/// MRPT's CPointsMap::TLikelihoodOptions, same defaults.
struct PointMapLikelihoodOptions {
  double sigma_dist = 0.0025;      ///< m², > 0
  double max_corr_distance = 1.0;  ///< meters, > 0
  std::uint32_t decimation = 10;   ///< use one scan point in this many, >= 1

  /// `sigma_dist`, `max_corr_distance`, `decimation` (MRPT's
  /// CPointsMap::TLikelihoodOptions) present in `section`, over the defaults.
  static PointMapLikelihoodOptions from_config(const ConfigSection& section);
};

/// See the file comment.
class PointMap {
 public:
  /// An empty map carrying `channels` (kColor: coloured map, kIntensity: XYZI).
  explicit PointMap(PointChannels channels = PointChannels::None);
  /// A map holding `cloud` (its channels included).
  explicit PointMap(PointCloud cloud);
  PointMap(const PointMap& other);
  PointMap& operator=(const PointMap& other);
  PointMap(PointMap&&) noexcept;
  PointMap& operator=(PointMap&&) noexcept;
  ~PointMap();

  PointMapInsertionOptions insertion_options;
  PointMapLikelihoodOptions likelihood_options;
  /// Color given to points that carry none (points from 2D scans).
  Rgb8 default_color{255, 255, 255};

  /// The points, map frame, meters.
  const PointCloud& cloud() const noexcept { return cloud_; }
  std::size_t size() const noexcept { return cloud_.size(); }
  bool empty() const noexcept { return cloud_.empty(); }
  /// Replaces the points (marks the KD-tree stale).
  void set_cloud(PointCloud cloud);
  /// Removes every point.
  void clear();
  /// Appends one point (channel values default; default_color for colors).
  void insert_point(const Eigen::Vector3f& p_map);

  /// Inserts a 2D scan taken with the robot at T_map_robot (MRPT's
  /// insertObservation: always adds; fuses if fuse_with_existing). Returns
  /// false if the map is planar and the scan is not. Precondition: scan.check().
  bool insert(const RangeScan2D& scan, const Pose3& T_map_robot);
  /// Inserts a 3D range image; false for a planar map (MRPT does the same).
  bool insert(const RangeImage3D& scan, const Pose3& T_map_robot);
  /// MRPT's loadFromRangeScan: as insert() without fusion, clearing the map
  /// first unless insertion_options.add_to_existing.
  void load_scan(const RangeScan2D& scan, const Pose3& T_map_robot);
  void load_scan(const RangeImage3D& scan, const Pose3& T_map_robot);

  /// MRPT's point-map observation likelihood: the scan's points (in the
  /// robot frame, loaded with default insertion options as MRPT's
  /// buildAuxPointsMap) are placed at T_map_robot; over one point in
  /// `decimation`, e_i = min(d_i², max_corr_distance²) with d_i the distance
  /// to the nearest map point — in XY when T_map_robot has zero pitch and
  /// roll (2D KD-tree), in 3D otherwise; returns −mean(e_i) / sigma_dist.
  /// −100 if the map or the scan has no point (MRPT's value).
  double log_likelihood(const RangeScan2D& scan, const Pose3& T_map_robot) const;
  /// As above for a 3D range image (always 3D distances).
  double log_likelihood(const RangeImage3D& scan, const Pose3& T_map_robot) const;

  /// The 3D KD-tree over the points (built on first use after a change).
  const KdTree3f& kdtree3() const;
  /// The 2D (XY) KD-tree over the points.
  const KdTree2f& kdtree2() const;

  /// Box of the finite points.
  BoundingBox3 bounding_box() const noexcept { return cloud_.bounding_box(); }
  /// Keeps only the points inside `box` (inclusive).
  void clip(const BoundingBox3& box);
  /// Maps every point (and normal) by T: p ← T ⊕ p (e.g. moving the map).
  void transform(const Pose3& T);
  /// Re-expresses the map in a new frame whose pose in the current frame is
  /// T_old_new: p ← T_old_new⁻¹ ⊕ p (MRPT's changeCoordinatesReference with
  /// the inverse pose).
  void change_frame(const Pose3& T_old_new) { transform(T_old_new.inverse()); }

 private:
  struct Trees;
  void touch();
  void append_scan_points(const std::vector<Eigen::Vector3f>& pts, const std::vector<Rgb8>* colors,
                          const std::vector<float>* intensity);
  void fuse_points(const std::vector<Eigen::Vector3f>& pts, bool allow_deletion);
  double likelihood_of(const std::vector<Eigen::Vector3f>& p_robot, const Pose3& T_map_robot, bool planar) const;

  PointCloud cloud_;
  std::unique_ptr<Trees> trees_;
};

namespace detail {
/// The points of a 2D scan in the frame of T_frame_robot, computed in
/// o.arithmetic and filtered with MRPT's loadFromRangeScan rules (see the
/// file comment); `ray_of` receives each point's ray index (-1 for
/// interpolated points).
std::vector<Eigen::Vector3f> scan_points(const RangeScan2D& scan, const Pose3& T_frame_robot,
                                         const PointMapInsertionOptions& o, std::vector<int>* ray_of);
/// The colour of each point (map frame) of `scan` taken with the robot at
/// T_map_robot: the pixel of the intensity image it projects to (black when
/// behind the camera, outside the image, or without an intensity image).
std::vector<Rgb8> range_image_colors(const RangeImage3D& scan, const Pose3& T_map_robot,
                                     const std::vector<Eigen::Vector3f>& p_map);
}  // namespace detail

}  // namespace rove
