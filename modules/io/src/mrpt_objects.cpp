// Readers of MRPT object payloads (MRPT's serializeFrom of each class, as of
// MRPT 2.x; field order and versions cited per class below).

#include "rove/io/mrpt_objects.h"

#include <fmt/format.h>

#include <cmath>
#include <cstdint>
#include <optional>
#include <iterator>
#include <string>
#include <utility>
#include <vector>

#include "mrpt_read_helpers.h"
#include "rove/core/error.h"
#include "rove/obs/beacon_ranges.h"
#include "rove/obs/bearing_range.h"
#include "rove/obs/odometry_observation.h"
#include "rove/obs/range_scan_2d.h"
#include "rove/obs/robot_movement_2d.h"
#include "rove/obs/timestamp.h"
#include "rove/poses/pose3_quat.h"
#include "rove/serialization/mrpt_class_readers.h"
#include "rove/serialization/mrpt_format.h"
#include "rove/serialization/parse_guard.h"

namespace rove {
namespace {


// MRPT accepts any stored matrix as a rotation; poses written from float
// data (older files) are orthonormal only to float precision.
constexpr double kMrptRotationTolerance = 1e-4;

template <typename T>
T expect(InArchive& ar, std::string_view field, const char* what) {
  return detail::expect_mrpt<T>(ar, field, what);
}

Timestamp read_timestamp(InArchive& ar, std::string_view field) {
  return detail::read_mrpt_timestamp(ar, field);
}

Twist2 read_twist2(InArchive& ar, std::string_view field) {
  // TTwist2D: vx, vy, omega as doubles.
  Twist2 t;
  t.vx = ar.read_scalar<double>(field);
  t.vy = ar.read_scalar<double>(field);
  t.omega = ar.read_scalar<double>(field);
  return t;
}

template <typename S, int N>
Eigen::Matrix<double, N, N> read_symmetric(InArchive& ar, std::string_view field) {
  return detail::read_mrpt_symmetric<S, N>(ar, field);
}

const char* alternative_name(std::size_t index) { return detail::mrpt_alternative_name(index); }

Pose3 pose3_from_matrix(InArchive& ar, std::uint64_t at, const Eigen::MatrixXd& m) {
  if (m.rows() != 4 || m.cols() != 4) {
    ar.fail_at(at, "CPose3D",
               fmt::format("expected a 4x4 matrix, found {}x{}", m.rows(), m.cols()));
  }
  return parse_guard(ar, at, "CPose3D", [&] {
    return Pose3(Eigen::Matrix3d(m.block<3, 3>(0, 0)), Eigen::Vector3d(m.block<3, 1>(0, 3)),
                 kMrptRotationTolerance);
  });
}

// CPose2D::serializeFrom: v0 three floats, v1 three doubles (x, y, phi).
MrptObject read_pose2(InArchive& ar, const MrptObjectHeader& h) {
  double v[3];
  if (h.version == 0) {
    for (double& x : v) x = ar.read_scalar<float>("CPose2D");
  } else if (h.version == 1) {
    for (double& x : v) x = ar.read_scalar<double>("CPose2D");
  } else {
    throw_unknown_mrpt_version(ar, h);
  }
  return parse_guard(ar, h.offset, "CPose2D", [&] { return Pose2(v[0], v[1], v[2]); });
}

// CPose3D::serializeFrom: v0 CMatrixF 4x4, v1 CMatrixD 4x4, v2 x y z qw qx
// qy qz, v3 x y z then the rotation row by row (doubles).
MrptObject read_pose3(InArchive& ar, const MrptObjectHeader& h) {
  switch (h.version) {
    case 0:
    case 1: {
      const auto m = expect<Eigen::MatrixXd>(ar, "CPose3D", "a matrix");
      return pose3_from_matrix(ar, h.offset, m);
    }
    case 2: {
      double p[7];
      for (double& x : p) x = ar.read_scalar<double>("CPose3D");
      return parse_guard(ar, h.offset, "CPose3D", [&] {
        return Pose3(Pose3Quat(p[0], p[1], p[2], p[3], p[4], p[5], p[6]));
      });
    }
    case 3: {
      Eigen::Vector3d t;
      Eigen::Matrix3d R;
      for (int i = 0; i < 3; ++i) t[i] = ar.read_scalar<double>("CPose3D");
      for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 3; ++c) R(r, c) = ar.read_scalar<double>("CPose3D");
      }
      return parse_guard(ar, h.offset, "CPose3D",
                         [&] { return Pose3(R, t, kMrptRotationTolerance); });
    }
    default:
      throw_unknown_mrpt_version(ar, h);
  }
}

MrptObject read_matrix_d(InArchive& ar, const MrptObjectHeader& h) {
  if (h.version != 0) throw_unknown_mrpt_version(ar, h);
  return Eigen::MatrixXd(read_mrpt_matrix<double>(ar, "CMatrixD"));
}

MrptObject read_matrix_f(InArchive& ar, const MrptObjectHeader& h) {
  if (h.version != 0) throw_unknown_mrpt_version(ar, h);
  return Eigen::MatrixXd(read_mrpt_matrix<float>(ar, "CMatrixF").cast<double>());
}

// CPosePDFGaussian::serializeFrom: mean (CPose2D object), then the
// covariance: v0 CMatrixF object, v1 symmetric floats, v2 symmetric doubles.
MrptObject read_pose2_gaussian(InArchive& ar, const MrptObjectHeader& h) {
  const Pose2 mean = expect<Pose2>(ar, "CPosePDFGaussian.mean", "CPose2D");
  Eigen::Matrix3d cov;
  switch (h.version) {
    case 0: {
      const std::uint64_t at = ar.offset();
      const auto m = expect<Eigen::MatrixXd>(ar, "CPosePDFGaussian.cov", "a matrix");
      if (m.rows() != 3 || m.cols() != 3) {
        ar.fail_at(at, "CPosePDFGaussian.cov",
                   fmt::format("expected a 3x3 matrix, found {}x{}", m.rows(), m.cols()));
      }
      cov = m;
      break;
    }
    case 1:
      cov = read_symmetric<float, 3>(ar, "CPosePDFGaussian.cov");
      break;
    case 2:
      cov = read_symmetric<double, 3>(ar, "CPosePDFGaussian.cov");
      break;
    default:
      throw_unknown_mrpt_version(ar, h);
  }
  return parse_guard(ar, h.offset, "CPosePDFGaussian", [&] { return Pose2Gaussian(mean, cov); });
}

// CPose3DPDFGaussian::serializeFrom v1: mean (CPose3D object), symmetric
// 6x6 covariance of doubles.
MrptObject read_pose3_gaussian(InArchive& ar, const MrptObjectHeader& h) {
  if (h.version != 1) throw_unknown_mrpt_version(ar, h);
  const Pose3 mean = expect<Pose3>(ar, "CPose3DPDFGaussian.mean", "CPose3D");
  const Eigen::Matrix<double, 6, 6> cov = read_symmetric<double, 6>(ar, "CPose3DPDFGaussian.cov");
  return parse_guard(ar, h.offset, "CPose3DPDFGaussian", [&] { return Pose3Gaussian(mean, cov); });
}

// CObservation2DRangeScan::serializeFrom, versions 0..8 (deltaPitch is a
// double, sweepDuration a float).
MrptObject read_range_scan_2d(InArchive& ar, const MrptObjectHeader& h) {
  constexpr std::string_view kField = "CObservation2DRangeScan";
  if (h.version > 8) throw_unknown_mrpt_version(ar, h);
  auto scan = std::make_shared<RangeScan2D>();
  scan->aperture = ar.read_scalar<float>(kField);
  scan->right_to_left = read_mrpt_bool(ar, kField);
  scan->max_range = ar.read_scalar<float>(kField);
  scan->T_robot_sensor = expect<Pose3>(ar, "CObservation2DRangeScan.sensorPose", "CPose3D");
  if (h.version < 6) {
    // covSensorPose (CMatrixF), removed in version 6; rove keeps no such field.
    expect<Eigen::MatrixXd>(ar, "CObservation2DRangeScan.covSensorPose", "a matrix");
  }
  const std::uint32_t n = ar.read_length("CObservation2DRangeScan.scan", sizeof(float));
  ar.append_scalars(scan->ranges, n, "CObservation2DRangeScan.scan");
  scan->valid.resize(n);
  if (h.version >= 1) {
    std::vector<std::uint8_t> flags;
    ar.append_scalars(flags, n, "CObservation2DRangeScan.validRange");
    for (std::uint32_t i = 0; i < n; ++i) scan->valid[i] = flags[i] != 0;
  } else {
    for (std::uint32_t i = 0; i < n; ++i) scan->valid[i] = scan->ranges[i] < scan->max_range;
  }
  if (h.version >= 2) scan->std_error = ar.read_scalar<float>(kField);
  if (h.version >= 3) scan->timestamp = read_timestamp(ar, "CObservation2DRangeScan.timestamp");
  if (h.version >= 4) scan->beam_aperture = ar.read_scalar<float>(kField);
  if (h.version >= 5) {
    scan->sensor_label = read_mrpt_string(ar, "CObservation2DRangeScan.sensorLabel");
    static_cast<void>(ar.read_scalar<double>("CObservation2DRangeScan.deltaPitch"));
  }
  if (h.version >= 7 && read_mrpt_bool(ar, "CObservation2DRangeScan.hasIntensity") && n > 0) {
    ar.append_scalars(scan->intensity, n, "CObservation2DRangeScan.intensity");
  }
  if (h.version >= 8) {
    static_cast<void>(ar.read_scalar<float>("CObservation2DRangeScan.sweepDuration"));
  }
  return std::shared_ptr<Observation>(std::move(scan));
}

// CObservationOdometry::serializeFrom, versions 0..2.
MrptObject read_odometry(InArchive& ar, const MrptObjectHeader& h) {
  if (h.version > 2) throw_unknown_mrpt_version(ar, h);
  auto odo = std::make_shared<OdometryObservation>();
  odo->odometry = expect<Pose2>(ar, "CObservationOdometry.odometry", "CPose2D");
  odo->sensor_label = read_mrpt_string(ar, "CObservationOdometry.sensorLabel");
  odo->timestamp = read_timestamp(ar, "CObservationOdometry.timestamp");
  if (h.version >= 1) {
    const bool has_encoders = read_mrpt_bool(ar, "CObservationOdometry.hasEncodersInfo");
    if (has_encoders || h.version < 2) {
      EncoderTicks ticks;
      ticks.left = ar.read_scalar<std::int32_t>("CObservationOdometry.encoderLeftTicks");
      ticks.right = ar.read_scalar<std::int32_t>("CObservationOdometry.encoderRightTicks");
      if (has_encoders) odo->encoder_ticks = ticks;
    }
    const bool has_velocities = read_mrpt_bool(ar, "CObservationOdometry.hasVelocities");
    if (h.version < 2) {
      Twist2 v;
      v.vx = ar.read_scalar<float>("CObservationOdometry.velocityLin");
      v.omega = ar.read_scalar<float>("CObservationOdometry.velocityAng");
      if (has_velocities) odo->velocity = v;
    } else if (has_velocities) {
      odo->velocity = read_twist2(ar, "CObservationOdometry.velocityLocal");
    }
  }
  return std::shared_ptr<Observation>(std::move(odo));
}

// CPoint3D::serializeFrom: v0 three floats, v1 three doubles.
MrptObject read_point3(InArchive& ar, const MrptObjectHeader& h) {
  double v[3];
  if (h.version == 0) {
    for (double& x : v) x = ar.read_scalar<float>("CPoint3D");
  } else if (h.version == 1) {
    for (double& x : v) x = ar.read_scalar<double>("CPoint3D");
  } else {
    throw_unknown_mrpt_version(ar, h);
  }
  return parse_guard(ar, h.offset, "CPoint3D", [&] { return Point3(v[0], v[1], v[2]); });
}

// CObservationBearingRange::serializeFrom, versions 0..3.
MrptObject read_bearing_range(InArchive& ar, const MrptObjectHeader& h) {
  constexpr std::string_view kField = "CObservationBearingRange";
  if (h.version > 3) throw_unknown_mrpt_version(ar, h);
  auto obs = std::make_shared<BearingRange>();
  obs->min_sensor_distance = ar.read_scalar<float>(kField);
  obs->max_sensor_distance = ar.read_scalar<float>(kField);
  if (h.version >= 3) {
    obs->field_of_view_yaw = ar.read_scalar<float>(kField);
    obs->field_of_view_pitch = ar.read_scalar<float>(kField);
  } else {
    obs->field_of_view_yaw = obs->field_of_view_pitch = ar.read_scalar<float>(kField);
  }
  obs->T_robot_sensor =
      expect<Pose3>(ar, "CObservationBearingRange.sensorLocationOnRobot", "CPose3D");
  if (h.version >= 2) obs->timestamp = read_timestamp(ar, "CObservationBearingRange.timestamp");
  bool valid_covariances = false;
  if (h.version >= 3) {
    valid_covariances = read_mrpt_bool(ar, "CObservationBearingRange.validCovariances");
    if (!valid_covariances) {
      obs->sensor_std_range = ar.read_scalar<float>(kField);
      obs->sensor_std_yaw = ar.read_scalar<float>(kField);
      obs->sensor_std_pitch = ar.read_scalar<float>(kField);
    }
  }
  // Each reading: range, yaw, pitch (floats), landmark id (i32), at least 16 bytes.
  const std::uint32_t n = ar.read_length("CObservationBearingRange.sensedData", 16);
  for (std::uint32_t i = 0; i < n; ++i) {
    LandmarkMeasurement m;
    m.range = ar.read_scalar<float>(kField);
    m.yaw = ar.read_scalar<float>(kField);
    m.pitch = ar.read_scalar<float>(kField);
    m.landmark_id = ar.read_scalar<std::int32_t>(kField);
    if (valid_covariances) {
      const std::uint64_t at = ar.offset();
      const auto c = expect<Eigen::MatrixXd>(ar, "CObservationBearingRange.covariance", "a matrix");
      if (c.rows() != 3 || c.cols() != 3) {
        ar.fail_at(at, "CObservationBearingRange.covariance",
                   fmt::format("expected a 3x3 matrix, found {}x{}", c.rows(), c.cols()));
      }
      m.covariance = Eigen::Matrix3d(c);
    }
    obs->measurements.push_back(std::move(m));
  }
  if (h.version >= 1) {
    obs->sensor_label = read_mrpt_string(ar, "CObservationBearingRange.sensorLabel");
  }
  return std::shared_ptr<Observation>(std::move(obs));
}

// auxEstimatePose, a CPose2D object read without Pose2's finiteness check:
// MRPT writes phi = -inf (and may write non-finite x, y) for "not
// estimated". Non-finite x or y: no estimate; non-finite phi: no heading.
std::optional<BeaconAuxEstimate> read_beacon_aux_estimate(InArchive& ar) {
  constexpr std::string_view kField = "CObservationBeaconRanges.auxEstimatePose";
  const InArchive::NestingGuard nesting(ar, kField);
  const MrptObjectHeader h = read_mrpt_object_header(ar);
  const bool is_pose2 = h.class_name == "CPose2D" || h.class_name == "mrpt::poses::CPose2D";
  if (h.is_null || !is_pose2) {
    ar.fail_at(h.offset, kField, fmt::format("expected CPose2D but found '{}'", h.class_name));
  }
  double v[3];
  if (h.version == 0) {
    for (double& x : v) x = ar.read_scalar<float>(kField);
  } else if (h.version == 1) {
    for (double& x : v) x = ar.read_scalar<double>(kField);
  } else {
    throw_unknown_mrpt_version(ar, h);
  }
  expect_mrpt_end_marker(ar, h);
  if (!std::isfinite(v[0]) || !std::isfinite(v[1])) return std::nullopt;
  BeaconAuxEstimate e;
  e.x_m = v[0];
  e.y_m = v[1];
  if (std::isfinite(v[2])) e.heading_rad = v[2];
  return e;
}

// CObservationBeaconRanges::serializeFrom, versions 0..3.
MrptObject read_beacon_ranges(InArchive& ar, const MrptObjectHeader& h) {
  constexpr std::string_view kField = "CObservationBeaconRanges";
  if (h.version > 3) throw_unknown_mrpt_version(ar, h);
  auto obs = std::make_shared<BeaconRanges>();
  obs->min_sensor_distance = ar.read_scalar<float>(kField);
  obs->max_sensor_distance = ar.read_scalar<float>(kField);
  obs->std_error = ar.read_scalar<float>(kField);
  // Each reading: a CPoint3D object, the distance (float), the id (u32).
  const std::uint32_t n = ar.read_length("CObservationBeaconRanges.sensedData", 16);
  for (std::uint32_t i = 0; i < n; ++i) {
    BeaconRange r;
    const Point3 p =
        expect<Point3>(ar, "CObservationBeaconRanges.sensorLocationOnRobot", "CPoint3D");
    r.position_on_robot = Eigen::Vector3d(p.x, p.y, p.z);
    r.range = ar.read_scalar<float>(kField);
    r.beacon_id = static_cast<std::int32_t>(ar.read_scalar<std::uint32_t>(kField));
    obs->readings.push_back(r);
  }
  if (h.version >= 1) obs->aux_estimate = read_beacon_aux_estimate(ar);
  if (h.version >= 2) {
    obs->sensor_label = read_mrpt_string(ar, "CObservationBeaconRanges.sensorLabel");
  }
  if (h.version >= 3) obs->timestamp = read_timestamp(ar, "CObservationBeaconRanges.timestamp");
  return std::shared_ptr<Observation>(std::move(obs));
}

// CActionRobotMovement2D::serializeFrom, versions 4..7.
MrptObject read_robot_movement_2d(InArchive& ar, const MrptObjectHeader& h) {
  constexpr std::string_view kField = "CActionRobotMovement2D";
  if (h.version < 4 || h.version > 7) throw_unknown_mrpt_version(ar, h);
  auto mv = std::make_shared<RobotMovement2D>();
  const std::uint64_t method_at = ar.offset();
  const auto method = ar.read_scalar<std::int32_t>("CActionRobotMovement2D.estimationMethod");
  if (method == 0) {  // emOdometry: raw increment + model configuration
    mv->odometry_increment =
        expect<Pose2>(ar, "CActionRobotMovement2D.rawOdometryIncrementReading", "CPose2D");
    const std::uint64_t model_at = ar.offset();
    const auto model = ar.read_scalar<std::int32_t>("CActionRobotMovement2D.modelSelection");
    if (model != 0 && model != 1) {
      ar.fail_at(model_at, "CActionRobotMovement2D.modelSelection",
                 fmt::format("unknown motion model {}", model));
    }
    MotionModelOptions& o = mv->motion_model;
    o.model = model == 0 ? MotionModel::Gaussian : MotionModel::Thrun;
    // Both parameter sets are stored in SI units (m, rad), as floats.
    o.gaussian.a1_m_per_m = ar.read_scalar<float>(kField);
    o.gaussian.a2_m_per_rad = ar.read_scalar<float>(kField);
    o.gaussian.a3_rad_per_m = ar.read_scalar<float>(kField);
    o.gaussian.a4_rad_per_rad = ar.read_scalar<float>(kField);
    o.gaussian.min_std_xy_m = ar.read_scalar<float>(kField);
    o.gaussian.min_std_phi_rad = ar.read_scalar<float>(kField);
    const auto particles = ar.read_scalar<std::int32_t>("CActionRobotMovement2D.nParticlesCount");
    o.thrun.particle_count = static_cast<std::uint32_t>(particles);
    o.thrun.alpha1_rot_rot = ar.read_scalar<float>(kField);
    o.thrun.alpha2_rot_trans_rad_per_m = ar.read_scalar<float>(kField);
    o.thrun.alpha3_trans_trans = ar.read_scalar<float>(kField);
    o.thrun.alpha4_trans_rot_m_per_rad = ar.read_scalar<float>(kField);
    if (h.version >= 5) {
      o.thrun.additional_std_xy_m = ar.read_scalar<float>(kField);
      o.thrun.additional_std_phi_rad = ar.read_scalar<float>(kField);
    } else {
      o.thrun.additional_std_xy_m = 0.0;
      o.thrun.additional_std_phi_rad = 0.0;
    }
    if (particles < 1) {
      ar.fail_at(model_at, "CActionRobotMovement2D.nParticlesCount",
                 fmt::format("particle count {} is not positive", particles));
    }
    parse_guard(ar, model_at, "CActionRobotMovement2D.motionModelConfiguration",
                [&] { o.check(); });
  } else if (method == 1) {  // emScan2DMatching: the PDF itself
    mv->estimated_pose_change =
        expect<Pose2Gaussian>(ar, "CActionRobotMovement2D.poseChange", "CPosePDFGaussian");
  } else {
    ar.fail_at(method_at, "CActionRobotMovement2D.estimationMethod",
               fmt::format("unknown estimation method {}", method));
  }
  const bool has_velocities = read_mrpt_bool(ar, "CActionRobotMovement2D.hasVelocities");
  if (h.version >= 7) {
    if (has_velocities) mv->velocity = read_twist2(ar, "CActionRobotMovement2D.velocityLocal");
  } else {
    Twist2 v;
    v.vx = ar.read_scalar<float>("CActionRobotMovement2D.velocityLin");
    v.omega = ar.read_scalar<float>("CActionRobotMovement2D.velocityAng");
    if (has_velocities) mv->velocity = v;
  }
  const bool has_encoders = read_mrpt_bool(ar, "CActionRobotMovement2D.hasEncodersInfo");
  if (h.version < 7 || has_encoders) {
    EncoderTicks ticks;
    ticks.left = ar.read_scalar<std::int32_t>("CActionRobotMovement2D.encoderLeftTicks");
    ticks.right = ar.read_scalar<std::int32_t>("CActionRobotMovement2D.encoderRightTicks");
    if (has_encoders) mv->encoder_ticks = ticks;
  }
  if (h.version >= 6) mv->timestamp = read_timestamp(ar, "CActionRobotMovement2D.timestamp");
  return std::shared_ptr<Action>(std::move(mv));
}

// CActionCollection::serializeFrom v0: u32 count, the actions.
MrptObject read_action_collection(InArchive& ar, const MrptObjectHeader& h) {
  if (h.version != 0) throw_unknown_mrpt_version(ar, h);
  const std::uint32_t n = ar.read_length("CActionCollection.count", 2);
  auto col = std::make_shared<ActionCollection>();
  for (std::uint32_t i = 0; i < n; ++i) {
    const std::uint64_t at = ar.offset();
    MrptObject o = read_mrpt_object(ar);
    if (std::holds_alternative<std::monostate>(o)) continue;
    auto* a = std::get_if<std::shared_ptr<Action>>(&o);
    if (a == nullptr) {
      ar.fail_at(at, "CActionCollection",
                 fmt::format("expected an action but found {}", alternative_name(o.index())));
    }
    col->add(std::move(*a));
  }
  return col;
}

// CSensoryFrame::serializeFrom v0..2: (v<2) u32 ID, (v0) u64 timestamp of
// every observation, u32 count, the observations.
MrptObject read_sensory_frame(InArchive& ar, const MrptObjectHeader& h) {
  if (h.version > 2) throw_unknown_mrpt_version(ar, h);
  if (h.version < 2) static_cast<void>(ar.read_scalar<std::uint32_t>("CSensoryFrame.ID"));
  Timestamp v0_time;
  if (h.version == 0) v0_time = read_timestamp(ar, "CSensoryFrame.timestamp");
  const std::uint32_t n = ar.read_length("CSensoryFrame.count", 2);
  auto sf = std::make_shared<SensoryFrame>();
  for (std::uint32_t i = 0; i < n; ++i) {
    const std::uint64_t at = ar.offset();
    MrptObject o = read_mrpt_object(ar);
    if (std::holds_alternative<std::monostate>(o)) continue;
    auto* obs = std::get_if<std::shared_ptr<Observation>>(&o);
    if (obs == nullptr) {
      ar.fail_at(at, "CSensoryFrame",
                 fmt::format("expected an observation but found {}", alternative_name(o.index())));
    }
    if (h.version == 0) (*obs)->timestamp = v0_time;
    sf->add(std::move(*obs));
  }
  return sf;
}

MrptClassReaders<MrptObject> make_readers() {
  MrptClassReaders<MrptObject> r;
  // MRPT 2.x writes class names with their namespace ("mrpt::obs::CSensoryFrame");
  // older files use the bare name. Both spellings are registered.
  const detail::MrptReaderAdder add = [&r](std::string_view ns, const std::string& name,
                                            MrptClassReaders<MrptObject>::Reader reader) {
    r.add(name, reader);
    r.add(std::string(ns) + name, std::move(reader));
  };
  add("mrpt::poses::", "CPose2D", read_pose2);
  add("mrpt::poses::", "CPose3D", read_pose3);
  add("mrpt::math::", "CMatrixD", read_matrix_d);
  add("mrpt::math::", "CMatrixF", read_matrix_f);
  r.add("CMatrix", read_matrix_f);  // CMatrixF's name in MRPT < 0.9 (a float matrix)
  add("mrpt::poses::", "CPosePDFGaussian", read_pose2_gaussian);
  add("mrpt::poses::", "CPose3DPDFGaussian", read_pose3_gaussian);
  add("mrpt::obs::", "CObservation2DRangeScan", read_range_scan_2d);
  add("mrpt::obs::", "CObservationOdometry", read_odometry);
  add("mrpt::obs::", "CObservationBearingRange", read_bearing_range);
  add("mrpt::obs::", "CObservationBeaconRanges", read_beacon_ranges);
  add("mrpt::poses::", "CPoint3D", read_point3);
  add("mrpt::obs::", "CActionRobotMovement2D", read_robot_movement_2d);
  add("mrpt::obs::", "CActionCollection", read_action_collection);
  add("mrpt::obs::", "CSensoryFrame", read_sensory_frame);
  r.add("CSensorialFrame", read_sensory_frame);  // its name in MRPT < 0.6
  detail::add_mrpt_pdf_readers(add);
  detail::add_mrpt_sensor_readers(add);
  return r;
}

const MrptClassReaders<MrptObject>& readers() {
  static const MrptClassReaders<MrptObject> r = make_readers();
  return r;
}

}  // namespace

MrptObject read_mrpt_object(InArchive& ar) { return readers().read_object(ar); }

bool is_supported_mrpt_class(std::string_view class_name) {
  return readers().contains(class_name);
}

}  // namespace rove
