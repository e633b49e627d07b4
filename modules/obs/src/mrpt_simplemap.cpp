// CSimpleMap::serializeFrom (MRPT 2.x): u32 count, then per keyframe the pose
// PDF object and the sensory frame object (version 0: a 2D pose PDF).

#include "rove/obs/mrpt_simplemap.h"

#include <fmt/format.h>

#include <cstdint>
#include <utility>
#include <variant>

#include "rove/obs/mrpt_objects.h"
#include "rove/serialization/input_file.h"
#include "rove/serialization/mrpt_format.h"

namespace rove {

SimpleMap read_mrpt_simplemap(InArchive& ar) {
  const InArchive::NestingGuard nesting(ar, "CSimpleMap");
  const MrptObjectHeader h = read_mrpt_object_header(ar);
  if (h.class_name != "CSimpleMap" && h.class_name != "CSensFrameProbSequence") {
    ar.fail_at(h.offset, h.class_name,
               fmt::format("expected a CSimpleMap, found class '{}'", h.class_name));
  }
  if (h.version > 1) throw_unknown_mrpt_version(ar, h);
  const std::uint32_t n = ar.read_length("CSimpleMap.count", 4);
  SimpleMap map;
  for (std::uint32_t i = 0; i < n; ++i) {
    SimpleMapKeyframe kf;
    const std::uint64_t pose_at = ar.offset();
    MrptObject pose = read_mrpt_object(ar);
    if (h.version == 0 && std::holds_alternative<Pose2Gaussian>(pose)) {
      kf.pose = to_3d(std::get<Pose2Gaussian>(pose));
    } else if (h.version == 1 && std::holds_alternative<Pose3Gaussian>(pose)) {
      kf.pose = std::get<Pose3Gaussian>(pose);
    } else {
      ar.fail_at(pose_at, "CSimpleMap.pose",
                 h.version == 0 ? "expected a CPosePDFGaussian" : "expected a CPose3DPDFGaussian");
    }
    const std::uint64_t sf_at = ar.offset();
    MrptObject sf = read_mrpt_object(ar);
    if (auto* p = std::get_if<std::shared_ptr<SensoryFrame>>(&sf)) {
      kf.frame = std::move(*p);
    } else if (std::holds_alternative<std::monostate>(sf)) {
      kf.frame = std::make_shared<const SensoryFrame>();
    } else {
      ar.fail_at(sf_at, "CSimpleMap.sf", "expected a CSensoryFrame");
    }
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
