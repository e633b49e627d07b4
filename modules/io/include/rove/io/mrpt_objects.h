#pragma once
/// \file
/// Reading objects from MRPT's binary serialization into rove types: the
/// classes found in MRPT rawlogs and simple maps.
///
/// Supported classes and versions (MRPT's serializeFrom), mapped to:
///  - CPose2D v0..1 → Pose2; CPose3D v0..3 → Pose3; CPoint3D v0..1 → Point3;
///  - CMatrixD v0, CMatrixF v0 (old name CMatrix) → Eigen::MatrixXd;
///  - CPosePDFGaussian v0..2 → Pose2Gaussian;
///    CPose3DPDFGaussian v1 → Pose3Gaussian;
///  - CObservation2DRangeScan v0..8 → RangeScan2D (MRPT's deltaPitch,
///    sweepDuration and the sensor-pose covariance of v0..5 have no rove
///    field and are dropped);
///  - CObservationOdometry v0..2 → OdometryObservation;
///  - CObservationBearingRange v0..3 → BearingRange;
///  - CObservationBeaconRanges v0..3 → BeaconRanges (auxEstimatePose →
///    aux_estimate; MRPT's −inf heading, "not estimated", → no heading);
///  - CPosePDFParticles v0..1, CPosePDFSOG v0..2 → Pose2Particles, Pose2SOG;
///    CPose3DPDFParticles v0..1, CPose3DPDFSOG v0, v2 → Pose3Particles, Pose3SOG;
///  - CActionRobotMovement3D v0..1 → RobotMovement3D;
///  - CObservationComment v0 → CommentObservation;
///  - CObservationRotatingScan v0 → RotatingScan;
///  - CObservationVelodyneScan v0..2 → VelodyneScan;
///  - CObservationGPS v1..11 → GpsObservation (NMEA GGA and RMC; TOPCON PZS
///    / SATS and other message types are rejected);
///  - CObservation3DRangeScan v0..10 → RangeImage3D, with CImage v2..9
///    (gray 8/16-bit/float and raw color; JPEG, zip and external files are
///    rejected) → Image and TCamera v0..6 (none / plumb_bob) → PinholeCamera;
///  - CActionRobotMovement2D v4..7 → RobotMovement2D (odometry increment and
///    motion model as stored; a stored PDF other than CPosePDFGaussian is
///    rejected);
///  - CActionCollection v0 → ActionCollection; CSensoryFrame v0..2 (old name CSensorialFrame) →
///    SensoryFrame (null entries, which MRPT allows, are left out).
/// Any other class or version is a rove::ParseError naming the source, the
/// byte offset of the object and the class. MRPT records carry no length, so
/// an object of an unknown class cannot be skipped.

#include <Eigen/Core>

#include <memory>
#include <string_view>
#include <variant>

#include "rove/obs/action.h"
#include "rove/obs/action_collection.h"
#include "rove/obs/image.h"
#include "rove/obs/observation.h"
#include "rove/obs/pinhole_camera.h"
#include "rove/obs/sensory_frame.h"
#include "rove/poses/pdf_gaussian2.h"
#include "rove/poses/pdf_gaussian3.h"
#include "rove/poses/pdf_particles.h"
#include "rove/poses/pdf_sog.h"
#include "rove/poses/point3.h"
#include "rove/poses/pose2.h"
#include "rove/poses/pose3.h"
#include "rove/serialization/archive.h"

namespace rove {

/// One MRPT object read into its rove counterpart; std::monostate for MRPT's
/// null object.
using MrptObject =
    std::variant<std::monostate, Eigen::MatrixXd, Pose2, Pose3, Pose2Gaussian, Pose3Gaussian,
                 std::shared_ptr<Observation>, std::shared_ptr<Action>,
                 std::shared_ptr<ActionCollection>, std::shared_ptr<SensoryFrame>, Point3,
                 Pose2Particles, Pose2SOG, Pose3Particles, Pose3SOG, Image, PinholeCamera>;

/// Reads one whole MRPT object (header, payload, end marker) at the current
/// position of `ar`. Throws rove::ParseError (source, byte offset, class) on
/// an unsupported class or version and on malformed or truncated data.
/// Thread-safety: distinct archives may be read concurrently.
MrptObject read_mrpt_object(InArchive& ar);

/// True if read_mrpt_object has a reader for `class_name` (e.g. "CPose2D").
bool is_supported_mrpt_class(std::string_view class_name);

}  // namespace rove
