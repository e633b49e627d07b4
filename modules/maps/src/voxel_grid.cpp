#include "rove/maps/voxel_grid.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "rove/core/check.h"

namespace rove {

namespace {

struct Keyed {
  std::uint64_t key;
  std::uint32_t index;
};

/// LSD radix sort on the low `bits` bits of the key, 11 bits per pass;
/// stable, so points keep input order inside a voxel (as std::sort of PCL's
/// pairs does not guarantee, but the centroid does not depend on it).
void radix_sort(std::vector<Keyed>& v, int bits) {
  constexpr int kDigit = 11;
  constexpr std::size_t kBuckets = std::size_t{1} << kDigit;
  std::vector<Keyed> tmp(v.size());
  std::vector<std::size_t> count(kBuckets);
  for (int shift = 0; shift < bits; shift += kDigit) {
    std::fill(count.begin(), count.end(), 0);
    for (const Keyed& k : v) ++count[(k.key >> shift) & (kBuckets - 1)];
    std::size_t sum = 0;
    for (auto& c : count) {
      const std::size_t n = c;
      c = sum;
      sum += n;
    }
    for (const Keyed& k : v) tmp[count[(k.key >> shift) & (kBuckets - 1)]++] = k;
    v.swap(tmp);
  }
}

struct Accum {
  Eigen::Vector3d xyz = Eigen::Vector3d::Zero();
  Eigen::Vector3d rgb = Eigen::Vector3d::Zero();
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  double intensity = 0;
  std::size_t n = 0;
};

}  // namespace

VoxelGridResult voxel_grid_filter(const PointCloud& cloud, const VoxelGridOptions& o) {
  for (int a = 0; a < 3; ++a) {
    ROVE_CHECK_FINITE(o.leaf_size[a]);
    ROVE_CHECK_GT(o.leaf_size[a], 0.0f);
  }
  ROVE_CHECK_LT(cloud.size(), std::size_t{1} << 32);
  const Eigen::Array3f inv = o.leaf_size.array().inverse();

  VoxelGridResult res;
  const std::size_t n = cloud.size();
  // Per-point voxel indices, PCL's float arithmetic.
  std::vector<std::array<std::int64_t, 3>> ijk;
  std::vector<std::uint32_t> idx;
  ijk.reserve(n);
  idx.reserve(n);
  std::array<std::int64_t, 3> lo{INT64_MAX, INT64_MAX, INT64_MAX}, hi{INT64_MIN, INT64_MIN, INT64_MIN};
  constexpr float kLimit = 4.611686e18f;  // 2^62
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3f& p = cloud[i];
    if (!p.allFinite()) continue;
    std::array<std::int64_t, 3> v;
    for (int a = 0; a < 3; ++a) {
      const float f = std::floor(p[a] * inv[a]);
      ROVE_CHECK_MSG(std::fabs(f) < kLimit, "point {} coordinate {} = {} over leaf {} leaves the voxel index range", i,
                     a, p[a], o.leaf_size[a]);
      v[static_cast<std::size_t>(a)] = static_cast<std::int64_t>(f);
      lo[static_cast<std::size_t>(a)] = std::min(lo[static_cast<std::size_t>(a)], v[static_cast<std::size_t>(a)]);
      hi[static_cast<std::size_t>(a)] = std::max(hi[static_cast<std::size_t>(a)], v[static_cast<std::size_t>(a)]);
    }
    ijk.push_back(v);
    idx.push_back(static_cast<std::uint32_t>(i));
  }
  res.finite_input = idx.size();
  const bool avg = o.average_channels;
  const bool col = avg && cloud.has_colors(), inten = avg && cloud.has_intensity(), nrm = avg && cloud.has_normals();
  PointChannels ch = PointChannels::kNone;
  if (col) ch = ch | PointChannels::kColor;
  if (inten) ch = ch | PointChannels::kIntensity;
  if (nrm) ch = ch | PointChannels::kNormal;
  res.cloud.set_channels(ch);
  if (idx.empty()) return res;

  // Grid extent per axis (each fits in uint64 since indices are within
  // ±2^62); the linear index is used when the whole grid fits in uint64.
  std::array<std::uint64_t, 3> dim;
  for (std::size_t a = 0; a < 3; ++a) dim[a] = static_cast<std::uint64_t>(hi[a] - lo[a]) + 1;
  std::uint64_t dxy = 0, cells = 0;
  const bool linear = !__builtin_mul_overflow(dim[0], dim[1], &dxy) && !__builtin_mul_overflow(dxy, dim[2], &cells);

  // Group the points by voxel: a run of equal keys is one voxel.
  std::vector<std::uint32_t> order(idx.size());
  std::vector<std::size_t> run_start;
  if (linear) {
    const std::uint64_t dx = dim[0];
    std::vector<Keyed> keyed(idx.size());
    std::uint64_t max_key = 0;
    for (std::size_t k = 0; k < idx.size(); ++k) {
      const std::uint64_t key = static_cast<std::uint64_t>(ijk[k][0] - lo[0]) +
                                static_cast<std::uint64_t>(ijk[k][1] - lo[1]) * dx +
                                static_cast<std::uint64_t>(ijk[k][2] - lo[2]) * dxy;
      keyed[k] = {key, static_cast<std::uint32_t>(k)};
      max_key = std::max(max_key, key);
    }
    const int bits = max_key == 0 ? 0 : 64 - __builtin_clzll(max_key);
    radix_sort(keyed, bits);
    for (std::size_t k = 0; k < keyed.size(); ++k) {
      order[k] = keyed[k].index;
      if (k == 0 || keyed[k].key != keyed[k - 1].key) run_start.push_back(k);
    }
  } else {
    // Grids beyond 2^64 cells: sort the (z, y, x) triples themselves.
    for (std::size_t k = 0; k < order.size(); ++k) order[k] = static_cast<std::uint32_t>(k);
    auto zyx = [&](std::uint32_t k) { return std::array<std::int64_t, 3>{ijk[k][2], ijk[k][1], ijk[k][0]}; };
    std::stable_sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) { return zyx(a) < zyx(b); });
    for (std::size_t k = 0; k < order.size(); ++k)
      if (k == 0 || ijk[order[k]] != ijk[order[k - 1]]) run_start.push_back(k);
  }
  run_start.push_back(order.size());
  res.occupied_voxels = run_start.size() - 1;

  res.cloud.reserve(res.occupied_voxels);
  for (std::size_t r = 0; r + 1 < run_start.size(); ++r) {
    const std::size_t b = run_start[r], e = run_start[r + 1];
    if (e - b < o.min_points_per_voxel) {
      ++res.dropped_voxels;
      continue;
    }
    Accum acc;
    for (std::size_t k = b; k < e; ++k) {
      const std::uint32_t i = idx[order[k]];
      acc.xyz += cloud[i].cast<double>();
      if (col) {
        const Rgb8 c = cloud.colors()[i];
        acc.rgb += Eigen::Vector3d(c.r, c.g, c.b);
      }
      if (inten) acc.intensity += cloud.intensities()[i];
      if (nrm) acc.normal += cloud.normals()[i].cast<double>();
    }
    const double m = static_cast<double>(e - b);
    const std::size_t j = res.cloud.push_back((acc.xyz / m).cast<float>());
    if (col) {
      const Eigen::Vector3d c = (acc.rgb / m).array().round();
      res.cloud.colors_mut()[j] = Rgb8{static_cast<std::uint8_t>(c[0]), static_cast<std::uint8_t>(c[1]),
                                       static_cast<std::uint8_t>(c[2])};
    }
    if (inten) res.cloud.intensities_mut()[j] = static_cast<float>(acc.intensity / m);
    if (nrm) {
      const double len = acc.normal.norm();
      res.cloud.normals_mut()[j] = len > 0 ? Eigen::Vector3f((acc.normal / len).cast<float>()) : Eigen::Vector3f::Zero();
    }
  }
  return res;
}

PointCloud voxel_downsample(const PointCloud& cloud, float leaf_size) {
  VoxelGridOptions o;
  o.leaf_size = Eigen::Vector3f::Constant(leaf_size);
  return voxel_grid_filter(cloud, o).cloud;
}

}  // namespace rove
