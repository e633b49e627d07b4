#include "rove/maps/pass_through.h"

#include <cmath>
#include <string>

#include "rove/core/check.h"

namespace rove {

PointField parse_point_field(std::string_view name) {
  if (name == "x") return PointField::X;
  if (name == "y") return PointField::Y;
  if (name == "z") return PointField::Z;
  if (name == "intensity") return PointField::Intensity;
  if (name == "normal_x") return PointField::NormalX;
  if (name == "normal_y") return PointField::NormalY;
  if (name == "normal_z") return PointField::NormalZ;
  ROVE_CHECK_MSG(false, "unknown point field '{}' (x, y, z, intensity, normal_x, normal_y, normal_z)",
                 std::string(name));
  return PointField::X;
}

PassThroughResult pass_through_filter(const PointCloud& cloud, const PassThroughOptions& o) {
  ROVE_CHECK(!std::isnan(o.min) && !std::isnan(o.max));
  ROVE_CHECK_LE(o.min, o.max);
  const bool wants_intensity = o.field == PointField::Intensity;
  const bool wants_normal =
      o.field == PointField::NormalX || o.field == PointField::NormalY || o.field == PointField::NormalZ;
  ROVE_CHECK_MSG(!wants_intensity || cloud.has_intensity(), "pass-through on intensity: the cloud has none");
  ROVE_CHECK_MSG(!wants_normal || cloud.has_normals(), "pass-through on a normal: the cloud has none");
  PassThroughResult res;
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const Eigen::Vector3f& p = cloud[i];
    if (!p.allFinite()) continue;
    float v = 0;
    switch (o.field) {
      case PointField::X: v = p.x(); break;
      case PointField::Y: v = p.y(); break;
      case PointField::Z: v = p.z(); break;
      case PointField::Intensity: v = cloud.intensities()[i]; break;
      case PointField::NormalX: v = cloud.normals()[i].x(); break;
      case PointField::NormalY: v = cloud.normals()[i].y(); break;
      case PointField::NormalZ: v = cloud.normals()[i].z(); break;
    }
    if (std::isnan(v)) continue;
    const bool inside = v >= o.min && v <= o.max;
    if (inside != o.negative) res.kept_indices.push_back(i);
  }
  res.cloud = cloud.select(res.kept_indices);
  return res;
}

}  // namespace rove
