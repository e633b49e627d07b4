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
#include <cstdlib>
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

// Walks the cells the segment origin → end crosses, as OctoMap's
// computeRayKeys: the origin's cell first, then each next cell; the end's
// cell is not visited, and nothing when both are in one cell. `key_origin`
// and `key_end` are the cells of origin and end. The cells are tracked by
// `cells`, a policy with
//   bool start(const OctreeKey& k)   the walk starts in cell k; false: stop
//   template <int Axis> bool advance(int step)
//                                    one cell along Axis (step ±1); false:
//                                    the cell is outside the policy's range,
//                                    stop (a ray would leave the tree there:
//                                    OctoMap's keys would wrap around)
//   bool at(const OctreeKey& k)      whether the current cell is k
//   void visit(int axis)             the current cell is crossed; entered
//                                    along `axis` (−1 for the origin's)
//
// The end's cell can only be reached after exactly as many steps as the
// keys of origin and end differ by (each axis moves one way), so the cell
// is compared with it only then. The state lives in scalars, not arrays
// indexed by the axis: a load that follows a store to an address known
// late (key[axis]) makes the processor replay the loop, which doubles its
// cost (the branches on the axis are cheaper: along a ray they repeat and
// are well predicted).
template <typename P, typename Cells>
inline void walk_ray(const P origin[3], const P end[3], const OctreeKey& key_origin, const OctreeKey& key_end,
                     double resolution, Cells& cells) {
  if (key_origin == key_end || !cells.start(key_origin)) return;
  cells.visit(-1);
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
  const double limit = static_cast<double>(length);
  const int st0 = step[0], st1 = step[1], st2 = step[2];
  long remaining = 0;
  for (int a = 0; a < 3; ++a) remaining += std::abs(static_cast<int>(key_end[a]) - static_cast<int>(key_origin[a]));
  while (true) {
    // OctoMap's choice: t0 < t1 ? (t0 < t2 ? 0 : 2) : (t1 < t2 ? 1 : 2).
    int axis;
    if (t0 < t1 && t0 < t2) {
      axis = 0, t0 += d0;
      if (!cells.template advance<0>(st0)) return;
    } else if (!(t0 < t1) && t1 < t2) {
      axis = 1, t1 += d1;
      if (!cells.template advance<1>(st1)) return;
    } else {
      axis = 2, t2 += d2;
      if (!cells.template advance<2>(st2)) return;
    }
    if (--remaining == 0 && cells.at(key_end)) return;
    // Past the end without entering its cell (rounding): stop, as OctoMap.
    if (std::min(std::min(t0, t1), t2) > limit) return;
    cells.visit(axis);
  }
}

// The walk_ray policy that hands each cell's key to emit(key, axis), within
// the tree.
template <typename Emit>
class KeyCells {
 public:
  explicit KeyCells(Emit& emit) : emit_(emit) {}
  bool start(const OctreeKey& k) noexcept {
    k0_ = k.x, k1_ = k.y, k2_ = k.z;
    return true;
  }
  template <int Axis>
  bool advance(int step) noexcept {
    int& k = Axis == 0 ? k0_ : (Axis == 1 ? k1_ : k2_);
    k += step;
    return static_cast<unsigned>(k) <= 0xFFFFu;
  }
  bool at(const OctreeKey& k) const noexcept { return k0_ == k.x && k1_ == k.y && k2_ == k.z; }
  void visit(int axis) {
    emit_(OctreeKey{static_cast<std::uint16_t>(k0_), static_cast<std::uint16_t>(k1_), static_cast<std::uint16_t>(k2_)},
          axis);
  }

 private:
  Emit& emit_;
  int k0_ = 0, k1_ = 0, k2_ = 0;
};

// Calls emit(key, axis) for every cell walk_ray visits.
template <typename P, typename Emit>
inline void traverse_ray(const P origin[3], const P end[3], const OctreeKey& key_origin, const OctreeKey& key_end,
                         double resolution, Emit&& emit) {
  KeyCells<std::remove_reference_t<Emit>> cells(emit);
  walk_ray(origin, end, key_origin, key_end, resolution, cells);
}

}  // namespace rove::detail
