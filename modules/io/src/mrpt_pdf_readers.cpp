// Readers of MRPT's sample-based and mixture pose PDFs (MRPT 2.5
// serializeFrom of CPosePDFParticles, CPosePDFSOG, CPose3DPDFParticles,
// CPose3DPDFSOG), and the helpers shared by all MRPT readers.

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <vector>

#include "mrpt_read_helpers.h"
#include "rove/core/error.h"

namespace rove::detail {

const char* mrpt_alternative_name(std::size_t index) {
  static constexpr const char* kNames[] = {
      "null object",        "matrix",           "CPose2D",           "CPose3D",
      "CPosePDFGaussian",   "CPose3DPDFGaussian", "observation",     "action",
      "CActionCollection",  "CSensoryFrame",    "CPoint3D",          "CPosePDFParticles",
      "CPosePDFSOG",        "CPose3DPDFParticles", "CPose3DPDFSOG",  "CImage",
      "TCamera"};
  static_assert(std::size(kNames) == std::variant_size_v<MrptObject>);
  return index < std::size(kNames) ? kNames[index] : "object";
}

Eigen::MatrixXd expect_mrpt_matrix(InArchive& ar, std::string_view field, Eigen::Index rows,
                                   Eigen::Index cols) {
  const std::uint64_t at = ar.offset();
  Eigen::MatrixXd m = expect_mrpt<Eigen::MatrixXd>(ar, field, "a matrix");
  if (m.rows() != rows || m.cols() != cols) {
    ar.fail_at(at, field,
               fmt::format("expected a {}x{} matrix, found {}x{}", rows, cols, m.rows(), m.cols()));
  }
  return m;
}

namespace {

// MRPT stores the weights of SOG version 0 linearly; it takes
// log(max(1e-300, w)).
double log_of_linear_weight(double w) { return std::log(std::max(1e-300, w)); }

Pose2 read_tpose2d(InArchive& ar, std::string_view field) {
  // TPose2D: x, y, phi (doubles, no object framing).
  const std::uint64_t at = ar.offset();
  double v[3];
  for (double& x : v) x = ar.read_scalar<double>(field);
  return parse_guard(ar, at, field, [&] { return Pose2(v[0], v[1], v[2]); });
}

Pose3 read_tpose3d(InArchive& ar, std::string_view field) {
  // TPose3D: x, y, z, yaw, pitch, roll (doubles, no object framing).
  const std::uint64_t at = ar.offset();
  double v[6];
  for (double& x : v) x = ar.read_scalar<double>(field);
  return parse_guard(ar, at, field, [&] { return Pose3(v[0], v[1], v[2], v[3], v[4], v[5]); });
}

// CParticleFilterData::readParticlesFromStream: u32 count, then per
// particle the log-weight (double) and the sample (version 0: a CPose2D /
// CPose3D object; version 1: a TPose2D / TPose3D, plain doubles).
template <typename Pose, typename ReadPlain>
PoseParticles<Pose> read_particles(InArchive& ar, const MrptObjectHeader& h, const char* pose_class,
                                   ReadPlain read_plain) {
  if (h.version > 1) throw_unknown_mrpt_version(ar, h);
  const std::string field = h.class_name + ".particles";
  // Each particle: 8 bytes of weight and at least 3 doubles (v1) or an object.
  const std::uint32_t n = ar.read_length(field, 8 + 24);
  std::vector<typename PoseParticles<Pose>::Particle> particles;
  particles.reserve(n);
  for (std::uint32_t i = 0; i < n; ++i) {
    const std::uint64_t at = ar.offset();
    typename PoseParticles<Pose>::Particle p;
    p.log_weight = ar.read_scalar<double>(field);
    if (!(std::isfinite(p.log_weight) || p.log_weight == -INFINITY)) {
      ar.fail_at(at, field, fmt::format("particle {} has log-weight {}", i, p.log_weight));
    }
    p.pose = h.version == 0 ? expect_mrpt<Pose>(ar, field, pose_class) : read_plain(ar, field);
    particles.push_back(p);
  }
  return parse_guard(ar, h.offset, h.class_name,
                     [&] { return PoseParticles<Pose>(std::move(particles)); });
}

MrptObject read_pose2_particles(InArchive& ar, const MrptObjectHeader& h) {
  return read_particles<Pose2>(ar, h, "CPose2D", read_tpose2d);
}

MrptObject read_pose3_particles(InArchive& ar, const MrptObjectHeader& h) {
  return read_particles<Pose3>(ar, h, "CPose3D", read_tpose3d);
}

// CPosePDFSOG v0..2: u32 count, then per mode the weight (v0 linear, else
// log), the mean (CPose2D object) and the symmetric 3x3 covariance (v1
// floats, else doubles).
MrptObject read_pose2_sog(InArchive& ar, const MrptObjectHeader& h) {
  if (h.version > 2) throw_unknown_mrpt_version(ar, h);
  const std::string_view field = "CPosePDFSOG.modes";
  const std::uint32_t n = ar.read_length(field, 8 + 24);
  std::vector<Pose2SOG::Mode> modes;
  modes.reserve(n);
  for (std::uint32_t i = 0; i < n; ++i) {
    const std::uint64_t at = ar.offset();
    double w = ar.read_scalar<double>(field);
    if (h.version == 0) w = log_of_linear_weight(w);
    const Pose2 mean = expect_mrpt<Pose2>(ar, field, "CPose2D");
    const Eigen::Matrix3d cov = h.version == 1 ? read_mrpt_symmetric<float, 3>(ar, field)
                                               : read_mrpt_symmetric<double, 3>(ar, field);
    modes.push_back(parse_guard(ar, at, field, [&] {
      return Pose2SOG::Mode{Pose2Gaussian(mean, cov), w};
    }));
  }
  return parse_guard(ar, h.offset, "CPosePDFSOG", [&] { return Pose2SOG(std::move(modes)); });
}

// CPose3DPDFSOG v0 and v2: u32 count, then per mode the weight (v0 linear,
// v2 log), the mean (CPose3D object) and the covariance (a 6x6 CMatrixD
// object). Version 1 stored floats; MRPT 2.5 itself no longer reads it.
MrptObject read_pose3_sog(InArchive& ar, const MrptObjectHeader& h) {
  if (h.version != 0 && h.version != 2) throw_unknown_mrpt_version(ar, h);
  const std::string_view field = "CPose3DPDFSOG.modes";
  const std::uint32_t n = ar.read_length(field, 8 + 24);
  std::vector<Pose3SOG::Mode> modes;
  modes.reserve(n);
  for (std::uint32_t i = 0; i < n; ++i) {
    const std::uint64_t at = ar.offset();
    double w = ar.read_scalar<double>(field);
    if (h.version == 0) w = log_of_linear_weight(w);
    const Pose3 mean = expect_mrpt<Pose3>(ar, field, "CPose3D");
    const Pose3Gaussian::Matrix cov = expect_mrpt_matrix(ar, field, 6, 6);
    modes.push_back(parse_guard(ar, at, field, [&] {
      return Pose3SOG::Mode{Pose3Gaussian(mean, cov), w};
    }));
  }
  return parse_guard(ar, h.offset, "CPose3DPDFSOG", [&] { return Pose3SOG(std::move(modes)); });
}

}  // namespace

void add_mrpt_pdf_readers(const MrptReaderAdder& add) {
  add("mrpt::poses::", "CPosePDFParticles", read_pose2_particles);
  add("mrpt::poses::", "CPosePDFSOG", read_pose2_sog);
  add("mrpt::poses::", "CPose3DPDFParticles", read_pose3_particles);
  add("mrpt::poses::", "CPose3DPDFSOG", read_pose3_sog);
}

}  // namespace rove::detail
