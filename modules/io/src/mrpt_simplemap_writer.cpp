#include "rove/io/mrpt_simplemap_writer.h"

#include <cstdint>
#include <filesystem>
#include <span>
#include <string_view>

#include "rove/core/check.h"
#include "rove/core/files.h"
#include "rove/obs/range_scan_2d.h"
#include "rove/poses/pose3.h"
#include "rove/serialization/archive.h"
#include "rove/serialization/file_stream.h"

namespace rove {
namespace {

constexpr std::uint8_t kEndMarker = 0x88;

class MrptWriter {
 public:
  explicit MrptWriter(OutArchive& ar) : ar_(ar) {}

  void begin(std::string_view class_name, std::uint8_t version) {
    ROVE_CHECK_LT(class_name.size(), std::size_t{128});
    ar_.write_scalar<std::uint8_t>(static_cast<std::uint8_t>(0x80 | class_name.size()));
    ar_.write_bytes(std::as_bytes(std::span(class_name.data(), class_name.size())));
    ar_.write_scalar<std::uint8_t>(version);
  }
  void end() { ar_.write_scalar<std::uint8_t>(kEndMarker); }

  void u8(std::uint8_t v) { ar_.write_scalar(v); }
  void u32(std::uint32_t v) { ar_.write_scalar(v); }
  void u64(std::uint64_t v) { ar_.write_scalar(v); }
  void f32(float v) { ar_.write_scalar(v); }
  void f64(double v) { ar_.write_scalar(v); }
  void str(std::string_view s) {
    u32(static_cast<std::uint32_t>(s.size()));
    ar_.write_bytes(std::as_bytes(std::span(s.data(), s.size())));
  }

  // CPose3D version 3: x y z, then the rotation matrix row by row.
  void pose3(const Pose3& p) {
    begin("mrpt::poses::CPose3D", 3);
    const Eigen::Vector3d t = p.translation();
    const Eigen::Matrix3d R = p.rotation();
    for (int i = 0; i < 3; ++i) f64(t[i]);
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) f64(R(r, c));
    }
    end();
  }

 private:
  OutArchive& ar_;
};

void write_scan(MrptWriter& w, const RangeScan2D& s) {
  w.begin("mrpt::obs::CObservation2DRangeScan", 7);
  w.f32(static_cast<float>(s.aperture));
  w.u8(s.right_to_left ? 1 : 0);
  w.f32(s.max_range);
  w.pose3(s.T_robot_sensor);
  w.u32(static_cast<std::uint32_t>(s.ranges.size()));
  for (float r : s.ranges) w.f32(r);
  for (std::size_t i = 0; i < s.ranges.size(); ++i) {
    w.u8(i < s.valid.size() && s.valid[i] ? 1 : 0);
  }
  w.f32(s.std_error);
  w.u64(s.timestamp.to_mrpt());
  w.f32(s.beam_aperture);
  w.str(s.sensor_label);
  w.f64(0.0);  // deltaPitch
  w.u8(0);     // hasIntensity
  w.end();
}

}  // namespace

SimpleMapWriteReport write_mrpt_simplemap(const std::string& path,
                                          const std::vector<SimpleMapEntry2D>& entries) {
  SimpleMapWriteReport report;
  std::vector<const SimpleMapEntry2D*> kept;
  for (const auto& e : entries) {
    ROVE_CHECK(e.observation != nullptr);
    if (dynamic_cast<const RangeScan2D*>(e.observation) != nullptr) {
      kept.push_back(&e);
    } else {
      ++report.skipped;
    }
  }
  write_file_atomically(path, [&](const std::filesystem::path& tmp) {
  FileOutStream out(tmp.string());
  OutArchive ar(out);
  MrptWriter w(ar);
  w.begin("mrpt::maps::CSimpleMap", 1);
  w.u32(static_cast<std::uint32_t>(kept.size()));
  for (const SimpleMapEntry2D* e : kept) {
    // The 2D Gaussian lifted to 3D (MRPT's CPose3DPDF::createFrom2D):
    // (x, y, phi) → (x, y, z, yaw, pitch, roll) with z, pitch, roll exact.
    Eigen::Matrix<double, 6, 6> cov = Eigen::Matrix<double, 6, 6>::Zero();
    const int map3[3] = {0, 1, 3};
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) cov(map3[r], map3[c]) = e->covariance(r, c);
    }
    w.begin("mrpt::poses::CPose3DPDFGaussian", 1);
    w.pose3(Pose3(e->pose));
    for (int i = 0; i < 6; ++i) w.f64(cov(i, i));
    for (int r = 0; r < 5; ++r) {
      for (int c = r + 1; c < 6; ++c) w.f64(cov(r, c));
    }
    w.end();
    w.begin("mrpt::obs::CSensoryFrame", 2);
    w.u32(1);
    write_scan(w, static_cast<const RangeScan2D&>(*e->observation));
    w.end();
    ++report.keyframes;
  }
  w.end();
  out.close();
  });
  return report;
}

}  // namespace rove
