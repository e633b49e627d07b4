#pragma once
// Ray traversal of the octree's finest cells (internal): the 3D DDA of
// Amanatides & Woo, "A Fast Voxel Traversal Algorithm for Ray Tracing"
// (Eurographics 1987), as OctoMap 1.9 runs it in computeRayKeys.
//
// The scalar P of points and directions selects the arithmetic
// (OctreeRayArithmetic): double, or float as OctoMap's point3d, in which
// case every rounding step of OctoMap is reproduced (float differences and
// squares, a norm whose square root is taken in double then rounded to
// float, the half-cell offset rounded to float) so the cells crossed are
// OctoMap's exactly, also for rays through cell corners. Distances along
// the ray (t) are double in both.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <type_traits>

#include "rove/maps/octree_key.h"

namespace rove::detail {

// OctoMap's coordToKeyChecked: floor(coordinate / resolution) + 32768, in
// double; false when not finite or outside the tree.
inline bool coord_to_key(double inv_resolution, double c, std::uint16_t& key) noexcept {
  const double f = std::floor(inv_resolution * c);
  if (!(f >= -32768.0 && f < 32768.0)) return false;
  key = static_cast<std::uint16_t>(static_cast<int>(f) + kOctreeKeyOffset);
  return true;
}

template <typename P>
inline bool point_to_key(double inv_resolution, const P p[3], OctreeKey& key) noexcept {
  return coord_to_key(inv_resolution, static_cast<double>(p[0]), key.x) &&
         coord_to_key(inv_resolution, static_cast<double>(p[1]), key.y) &&
         coord_to_key(inv_resolution, static_cast<double>(p[2]), key.z);
}

// Centre of a finest cell along one axis (OctoMap's keyToCoord).
inline double key_to_coord(double resolution, std::uint16_t key) noexcept {
  return (static_cast<double>(static_cast<int>(key) - kOctreeKeyOffset) + 0.5) * resolution;
}

// Length of d (OctoMap's Vector3::norm for float: squares summed in float,
// square root in double).
template <typename P>
inline double norm3(const P d[3]) noexcept {
  const P sq = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
  return std::sqrt(static_cast<double>(sq));
}

// d / |d| (OctoMap's Vector3::normalized: divided by the norm rounded to P).
template <typename P>
inline void normalize3(P d[3]) noexcept {
  const double len = norm3(d);
  if (len > 0.0) {
    const P l = static_cast<P>(len);
    for (int i = 0; i < 3; ++i) d[i] /= l;
  }
}

// DDA set-up shared by ray traversal and ray casting from the cell `start`
// along the unit direction `dir`. `half_in_float`: OctoMap's computeRayKeys
// rounds the half-cell offset to float, its castRay does not.
template <typename P>
inline void dda_setup(const P origin[3], const P dir[3], const OctreeKey& start, double resolution,
                      bool half_in_float, int step[3], double t_max[3], double t_delta[3]) noexcept {
  for (int i = 0; i < 3; ++i) {
    step[i] = dir[i] > P(0) ? 1 : (dir[i] < P(0) ? -1 : 0);
    if (step[i] != 0) {
      double border = key_to_coord(resolution, start[i]);
      const double half = step[i] * resolution * 0.5;
      border += half_in_float ? static_cast<double>(static_cast<float>(half)) : half;
      t_max[i] = (border - static_cast<double>(origin[i])) / static_cast<double>(dir[i]);
      t_delta[i] = resolution / static_cast<double>(std::fabs(dir[i]));
    } else {
      t_max[i] = std::numeric_limits<double>::max();
      t_delta[i] = std::numeric_limits<double>::max();
    }
  }
}

// The axis whose cell border the ray meets first, with OctoMap's ties:
// t0 < t1 ? (t0 < t2 ? 0 : 2) : (t1 < t2 ? 1 : 2), without branches (the
// choice is what a traversal cannot predict).
inline int dda_axis(const double t_max[3]) noexcept {
  const int c01 = t_max[0] < t_max[1], c02 = t_max[0] < t_max[2], c12 = t_max[1] < t_max[2];
  return 2 - 2 * (c01 & c02) - ((c01 ^ 1) & c12);
}

// Calls emit(key, axis) for every cell the segment origin → end crosses:
// the origin's cell first (axis −1), then each next cell with the axis it
// was entered along; the end's cell is not emitted, and nothing when both
// are in one cell (OctoMap's computeRayKeys). `key_origin` and `key_end`
// are the cells of origin and end. A ray that would leave the tree stops
// there (OctoMap's keys would wrap around).
//
// The state lives in scalars, not arrays indexed by the axis: a load that
// follows a store to an address known late (key[axis]) makes the processor
// replay the loop, which doubles its cost (the branches on the axis are
// cheaper: along a ray they repeat and are well predicted).
template <typename P, typename Emit>
inline void traverse_ray(const P origin[3], const P end[3], const OctreeKey& key_origin,
                         const OctreeKey& key_end, double resolution, Emit&& emit) {
  if (key_origin == key_end) return;
  emit(key_origin, -1);
  P dir[3] = {end[0] - origin[0], end[1] - origin[1], end[2] - origin[2]};
  const P length = static_cast<P>(norm3(dir));
  if (!(length > P(0)) || !std::isfinite(length)) return;
  for (P& d : dir) d /= length;
  int step[3];
  double t_max[3], t_delta[3];
  dda_setup(origin, dir, key_origin, resolution, std::is_same_v<P, float>, step, t_max, t_delta);
  if (step[0] == 0 && step[1] == 0 && step[2] == 0) return;
  double t0 = t_max[0], t1 = t_max[1], t2 = t_max[2];
  const double d0 = t_delta[0], d1 = t_delta[1], d2 = t_delta[2];
  int k0 = key_origin.x, k1 = key_origin.y, k2 = key_origin.z;
  const int e0 = key_end.x, e1 = key_end.y, e2 = key_end.z;
  const double limit = static_cast<double>(length);
  const int st0 = step[0], st1 = step[1], st2 = step[2];
  while (true) {
    // OctoMap's choice: t0 < t1 ? (t0 < t2 ? 0 : 2) : (t1 < t2 ? 1 : 2).
    int axis;
    if (t0 < t1 && t0 < t2) {
      axis = 0, k0 += st0, t0 += d0;
    } else if (!(t0 < t1) && t1 < t2) {
      axis = 1, k1 += st1, t1 += d1;
    } else {
      axis = 2, k2 += st2, t2 += d2;
    }
    if (((k0 | k1 | k2) & ~0xFFFF) != 0) return;
    if (((k0 ^ e0) | (k1 ^ e1) | (k2 ^ e2)) == 0) return;
    // Past the end without entering its cell (rounding): stop, as OctoMap.
    if (std::min(std::min(t0, t1), t2) > limit) return;
    emit(OctreeKey{static_cast<std::uint16_t>(k0), static_cast<std::uint16_t>(k1), static_cast<std::uint16_t>(k2)},
         axis);
  }
}

}  // namespace rove::detail
