// CSimpleMap::serializeFrom (MRPT 2.x): u32 count, then per keyframe the pose
// PDF object and the sensory frame object (version 0: a 2D pose PDF), and
// (version 2) the local twist as MRPT's std::optional<TTwist3D>: strings
// "std::optional" and "TTwist3D", bool, then six doubles if present.

#include "rove/io/mrpt_simplemap.h"

#include <fmt/format.h>

#include <cstdint>
#include <utility>
#include <variant>

#include "rove/io/mrpt_objects.h"
#include "rove/serialization/input_file.h"
#include "rove/serialization/mrpt_format.h"

namespace rove {

Pose3 KeyframePosePdf::mean() const {
  return std::visit([](const auto& p) { return Pose3(p.mean()); }, pdf);
}

Eigen::Matrix<double, 6, 6> KeyframePosePdf::covariance() const {
  return std::visit([](const auto& p) { return Eigen::Matrix<double, 6, 6>(p.covariance()); },
                    pdf);
}

KeyframePosePdf keyframe_pdf_from_2d(const Pose2Gaussian& g) { return {to_3d(g)}; }

KeyframePosePdf keyframe_pdf_from_2d(const Pose2Particles& p) {
  std::vector<Pose3Particles::Particle> out;
  out.reserve(p.size());
  for (const auto& q : p.particles()) out.push_back({Pose3(q.pose), q.log_weight});
  return {Pose3Particles(std::move(out))};
}

KeyframePosePdf keyframe_pdf_from_2d(const Pose2SOG& s) {
  std::vector<Pose3SOG::Mode> out;
  out.reserve(s.size());
  for (const auto& m : s.modes()) out.push_back({to_3d(m.gaussian), m.log_weight});
  return {Pose3SOG(std::move(out))};
}

namespace {

KeyframePosePdf read_keyframe_pose(InArchive& ar, std::uint8_t version) {
  const std::uint64_t at = ar.offset();
  MrptObject pose = read_mrpt_object(ar);
  if (version == 0) {
    if (auto* g = std::get_if<Pose2Gaussian>(&pose)) return keyframe_pdf_from_2d(*g);
    if (auto* p = std::get_if<Pose2Particles>(&pose)) return keyframe_pdf_from_2d(*p);
    if (auto* s = std::get_if<Pose2SOG>(&pose)) return keyframe_pdf_from_2d(*s);
    ar.fail_at(at, "CSimpleMap.pose",
               "expected a 2D pose PDF (CPosePDFGaussian, CPosePDFParticles or CPosePDFSOG)");
  }
  if (auto* g = std::get_if<Pose3Gaussian>(&pose)) return {std::move(*g)};
  if (auto* p = std::get_if<Pose3Particles>(&pose)) return {std::move(*p)};
  if (auto* s = std::get_if<Pose3SOG>(&pose)) return {std::move(*s)};
  ar.fail_at(at, "CSimpleMap.pose",
             "expected a 3D pose PDF (CPose3DPDFGaussian, CPose3DPDFParticles or CPose3DPDFSOG)");
}

std::optional<Twist3> read_optional_twist(InArchive& ar) {
  constexpr std::string_view kField = "CSimpleMap.localTwist";
  const std::uint64_t at = ar.offset();
  const std::string container = read_mrpt_string(ar, kField);
  const std::string type = read_mrpt_string(ar, kField);
  if (container != "std::optional" || type != "TTwist3D") {
    ar.fail_at(at, kField,
               fmt::format("expected std::optional<TTwist3D>, found {}<{}>", container, type));
  }
  if (!read_mrpt_bool(ar, kField)) return std::nullopt;
  Twist3 t;
  for (double* v : {&t.vx, &t.vy, &t.vz, &t.wx, &t.wy, &t.wz}) *v = ar.read_scalar<double>(kField);
  return t;
}

}  // namespace

SimpleMap read_mrpt_simplemap(InArchive& ar) {
  const InArchive::NestingGuard nesting(ar, "CSimpleMap");
  const MrptObjectHeader h = read_mrpt_object_header(ar);
  if (h.class_name != "CSimpleMap" && h.class_name != "CSensFrameProbSequence" &&
      h.class_name != "mrpt::maps::CSimpleMap") {
    ar.fail_at(h.offset, h.class_name,
               fmt::format("expected a CSimpleMap, found class '{}'", h.class_name));
  }
  if (h.version > 2) throw_unknown_mrpt_version(ar, h);
  const std::uint32_t n = ar.read_length("CSimpleMap.count", 4);
  SimpleMap map;
  for (std::uint32_t i = 0; i < n; ++i) {
    SimpleMapKeyframe kf;
    kf.pose = read_keyframe_pose(ar, h.version);
    const std::uint64_t sf_at = ar.offset();
    MrptObject sf = read_mrpt_object(ar);
    if (auto* p = std::get_if<std::shared_ptr<SensoryFrame>>(&sf)) {
      kf.frame = std::move(*p);
    } else if (std::holds_alternative<std::monostate>(sf)) {
      kf.frame = std::make_shared<const SensoryFrame>();
    } else {
      ar.fail_at(sf_at, "CSimpleMap.sf", "expected a CSensoryFrame");
    }
    if (h.version >= 2) kf.local_twist = read_optional_twist(ar);
    map.keyframes.push_back(std::move(kf));
  }
  expect_mrpt_end_marker(ar, h);
  return map;
}

SimpleMap load_mrpt_simplemap(const std::string& path, ArchiveLimits limits) {
  const auto stream = open_input_file(path);
  InArchive ar(*stream, limits);
  SimpleMap map = read_mrpt_simplemap(ar);
  if (!ar.at_end()) ar.fail("CSimpleMap", "unexpected bytes after the simple map");
  return map;
}

}  // namespace rove
