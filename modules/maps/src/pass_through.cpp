#include "rove/maps/pass_through.h"

#include <cmath>
#include <string>

#include "rove/core/check.h"

namespace rove {

PointField parse_point_field(std::string_view name) {
  if (name == "x") return PointField::kX;
  if (name == "y") return PointField::kY;
  if (name == "z") return PointField::kZ;
  if (name == "intensity") return PointField::kIntensity;
  if (name == "normal_x") return PointField::kNormalX;
  if (name == "normal_y") return PointField::kNormalY;
  if (name == "normal_z") return PointField::kNormalZ;
  ROVE_CHECK_MSG(false, "unknown point field '{}' (x, y, z, intensity, normal_x, normal_y, normal_z)",
                 std::string(name));
  return PointField::kX;
}

PassThroughResult pass_through_filter(const PointCloud& cloud, const PassThroughOptions& o) {
  ROVE_CHECK(!std::isnan(o.min) && !std::isnan(o.max));
  ROVE_CHECK_LE(o.min, o.max);
  const bool wants_intensity = o.field == PointField::kIntensity;
  const bool wants_normal =
      o.field == PointField::kNormalX || o.field == PointField::kNormalY || o.field == PointField::kNormalZ;
  ROVE_CHECK_MSG(!wants_intensity || cloud.has_intensity(), "pass-through on intensity: the cloud has none");
  ROVE_CHECK_MSG(!wants_normal || cloud.has_normals(), "pass-through on a normal: the cloud has none");
  PassThroughResult res;
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const Eigen::Vector3f& p = cloud[i];
    if (!p.allFinite()) continue;
    float v = 0;
    switch (o.field) {
      case PointField::kX: v = p.x(); break;
      case PointField::kY: v = p.y(); break;
      case PointField::kZ: v = p.z(); break;
      case PointField::kIntensity: v = cloud.intensities()[i]; break;
      case PointField::kNormalX: v = cloud.normals()[i].x(); break;
      case PointField::kNormalY: v = cloud.normals()[i].y(); break;
      case PointField::kNormalZ: v = cloud.normals()[i].z(); break;
    }
    if (std::isnan(v)) continue;
    const bool inside = v >= o.min && v <= o.max;
    if (inside != o.negative) res.kept_indices.push_back(i);
  }
  res.cloud = cloud.select(res.kept_indices);
  return res;
}

}  // namespace rove
