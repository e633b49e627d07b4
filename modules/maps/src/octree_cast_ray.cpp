// OccupancyOctree::ray_keys and cast_ray (OctoMap's computeRayKeys and
// castRay), in either arithmetic (octree_rays.h).
#include <cmath>

#include <fmt/format.h>

#include "octree_rays.h"
#include "octree_store.h"
#include "octree_update.h"
#include "rove/core/check.h"
#include "rove/core/error.h"

namespace rove {

namespace {

template <typename P>
void to_p(const Eigen::Vector3d& v, P out[3]) {
  for (int i = 0; i < 3; ++i) out[i] = static_cast<P>(v[i]);
}

template <typename P>
OctreeKey checked_key(const OccupancyOctree& tree, const P p[3], const char* what) {
  OctreeKey k;
  if (!std::isfinite(static_cast<double>(p[0])) || !std::isfinite(static_cast<double>(p[1])) ||
      !std::isfinite(static_cast<double>(p[2])) || !detail::point_to_key(1.0 / tree.resolution(), p, k)) {
    throw InvalidArgument(fmt::format("{} ({}, {}, {}) is not finite or outside the octree (±{} m)", what, p[0], p[1],
                                      p[2], kOctreeKeyOffset * tree.resolution()));
  }
  return k;
}

template <typename P>
std::vector<OctreeKey> keys_of_ray(const OccupancyOctree& tree, const Eigen::Vector3d& origin,
                                   const Eigen::Vector3d& end) {
  P o[3], e[3];
  to_p(origin, o);
  to_p(end, e);
  const OctreeKey ko = checked_key(tree, o, "ray origin");
  const OctreeKey ke = checked_key(tree, e, "ray end");
  std::vector<OctreeKey> out;
  detail::traverse_ray(o, e, ko, ke, tree.resolution(), [&](const OctreeKey& k, int) { out.push_back(k); });
  return out;
}

template <typename P>
OctreeRayCastResult cast(const OccupancyOctree& tree, const detail::OctreeStore& store, const Eigen::Vector3d& origin,
                         const Eigen::Vector3d& direction, const OctreeRayCastOptions& options) {
  const double res = tree.resolution();
  P o[3], dir[3];
  to_p(origin, o);
  to_p(direction, dir);
  OctreeRayCastResult r;
  r.key = checked_key(tree, o, "ray origin");
  detail::LeafFinder finder(store);
  const auto state = [&](const OctreeKey& k) {
    // 0 unknown, 1 free, 2 occupied
    std::uint32_t id = 0;
    int depth = 0;
    if (!finder.find(k, id, depth)) return 0;
    return tree.is_occupied(store.node(id).log_odds) ? 2 : 1;
  };
  const auto stop = [&](OctreeRayCastTermination t) {
    r.termination = t;
    r.end = tree.center_of(r.key);
    return r;
  };
  const int start = state(r.key);
  if (start == 2) return stop(OctreeRayCastTermination::Hit);
  if (start == 0 && !options.ignore_unknown) return stop(OctreeRayCastTermination::Unknown);

  detail::normalize3(dir);  // OctoMap: directionP.normalized()
  int step[3];
  double t_max[3], t_delta[3];
  detail::dda_setup(o, dir, r.key, res, false, step, t_max, t_delta);
  ROVE_CHECK_MSG(step[0] != 0 || step[1] != 0 || step[2] != 0, "cast_ray: direction ({}, {}, {}) is zero",
                 direction.x(), direction.y(), direction.z());
  const bool limited = options.max_range > 0.0;
  const double max_sq = options.max_range * options.max_range;
  while (true) {
    const int axis = detail::dda_axis(t_max);
    if ((step[axis] < 0 && r.key[axis] == 0) || (step[axis] > 0 && r.key[axis] == 0xFFFF)) {
      return stop(OctreeRayCastTermination::EdgeOfMap);
    }
    r.key[axis] = static_cast<std::uint16_t>(r.key[axis] + step[axis]);
    t_max[axis] += t_delta[axis];
    if (limited) {
      // Distance from the origin to the cell's centre (OctoMap: float
      // differences and squares, summed in double).
      double dist_sq = 0.0;
      for (int j = 0; j < 3; ++j) {
        const P c = static_cast<P>(detail::key_to_coord(res, r.key[j]));
        const P dj = c - o[j];
        dist_sq += static_cast<double>(dj * dj);
      }
      if (dist_sq > max_sq) return stop(OctreeRayCastTermination::MaxRange);
    }
    const int s = state(r.key);
    if (s == 2) return stop(OctreeRayCastTermination::Hit);
    if (s == 0 && !options.ignore_unknown) return stop(OctreeRayCastTermination::Unknown);
  }
}

}  // namespace

std::vector<OctreeKey> OccupancyOctree::ray_keys(const Eigen::Vector3d& origin, const Eigen::Vector3d& end,
                                                 OctreeRayArithmetic arithmetic) const {
  if (arithmetic == OctreeRayArithmetic::OctoMap) return keys_of_ray<float>(*this, origin, end);
  return keys_of_ray<double>(*this, origin, end);
}

OctreeRayCastResult OccupancyOctree::cast_ray(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction,
                                              const OctreeRayCastOptions& options) const {
  ROVE_CHECK_MSG(direction.allFinite() && direction.squaredNorm() > 0.0,
                 "cast_ray: direction ({}, {}, {}) must be finite and not zero", direction.x(), direction.y(),
                 direction.z());
  ROVE_CHECK_MSG(!std::isnan(options.max_range), "cast_ray: max_range is NaN");
  if (options.arithmetic == OctreeRayArithmetic::OctoMap) {
    return cast<float>(*this, detail::OctreeAccess::store(*this), origin, direction, options);
  }
  return cast<double>(*this, detail::OctreeAccess::store(*this), origin, direction, options);
}

}  // namespace rove
