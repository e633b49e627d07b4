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

/// LSD radix sort on bits [shift0, shift0 + bits) of key(v), 11 bits per
/// pass; stable, so points keep input order inside a voxel.
template <typename T, typename Key>
void radix_sort(std::vector<T>& v, int shift0, int bits, Key key) {
  constexpr int kDigit = 11;
  constexpr std::size_t kBuckets = std::size_t{1} << kDigit;
  if (bits <= 0) return;
  std::vector<T> tmp(v.size());
  std::vector<std::size_t> count(kBuckets);
  for (int shift = shift0; shift < shift0 + bits; shift += kDigit) {
    std::fill(count.begin(), count.end(), 0);
    for (const T& x : v) ++count[(key(x) >> shift) & (kBuckets - 1)];
    std::size_t sum = 0;
    for (auto& c : count) {
      const std::size_t m = c;
      c = sum;
      sum += m;
    }
    for (const T& x : v) tmp[count[(key(x) >> shift) & (kBuckets - 1)]++] = x;
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
  // Voxel index of a coordinate: PCL's floor(x * inv) in float, with an
  // exact integer floor (no libm call) once |x * inv| < 2^62 is checked.
  constexpr float kLimit = 4.611686e18f;  // 2^62
  auto index_of = [&](std::size_t i, int a) -> std::int64_t {
    const float f = cloud[i][a] * inv[a];
    ROVE_CHECK_MSG(std::fabs(f) < kLimit, "point {} coordinate {} = {} over leaf {} leaves the voxel index range", i,
                   a, cloud[i][a], o.leaf_size[a]);
    const auto t = static_cast<std::int64_t>(f);
    return static_cast<float>(t) > f ? t - 1 : t;
  };
  // Pass 1: index range per axis (nothing stored).
  std::array<std::int64_t, 3> lo{INT64_MAX, INT64_MAX, INT64_MAX}, hi{INT64_MIN, INT64_MIN, INT64_MIN};
  for (std::size_t i = 0; i < n; ++i) {
    if (!cloud[i].allFinite()) continue;
    ++res.finite_input;
    for (int a = 0; a < 3; ++a) {
      const std::int64_t v = index_of(i, a);
      lo[static_cast<std::size_t>(a)] = std::min(lo[static_cast<std::size_t>(a)], v);
      hi[static_cast<std::size_t>(a)] = std::max(hi[static_cast<std::size_t>(a)], v);
    }
  }
  const bool avg = o.average_channels;
  const bool col = avg && cloud.has_colors(), inten = avg && cloud.has_intensity(), nrm = avg && cloud.has_normals();
  PointChannels ch = PointChannels::None;
  if (col) ch = ch | PointChannels::Color;
  if (inten) ch = ch | PointChannels::Intensity;
  if (nrm) ch = ch | PointChannels::Normal;
  res.cloud.set_channels(ch);
  if (res.finite_input == 0) return res;

  // Grid extent per axis (each fits in uint64 since indices are within
  // ±2^62); the linear index is used when the whole grid fits in uint64.
  std::array<std::uint64_t, 3> dim;
  for (std::size_t a = 0; a < 3; ++a) dim[a] = static_cast<std::uint64_t>(hi[a] - lo[a]) + 1;
  std::uint64_t dxy = 0, cells = 0;
  const bool linear = !__builtin_mul_overflow(dim[0], dim[1], &dxy) && !__builtin_mul_overflow(dxy, dim[2], &cells);

  // Pass 2: group the points by voxel; order[] lists point indices so that
  // a run of equal voxels is consecutive.
  std::vector<std::uint32_t> order(res.finite_input);
  std::vector<std::size_t> run_start;
  if (linear) {
    const std::uint64_t dx = dim[0];
    auto key_of = [&](std::size_t i) {
      return static_cast<std::uint64_t>(index_of(i, 0) - lo[0]) +
             static_cast<std::uint64_t>(index_of(i, 1) - lo[1]) * dx +
             static_cast<std::uint64_t>(index_of(i, 2) - lo[2]) * dxy;
    };
    const int key_bits = cells <= 1 ? 0 : 64 - __builtin_clzll(cells - 1);
    const int idx_bits = n <= 1 ? 1 : 64 - __builtin_clzll(static_cast<std::uint64_t>(n - 1));
    if (key_bits + idx_bits <= 64) {
      // Key and point index packed in one word: half the memory traffic.
      std::vector<std::uint64_t> packed;
      packed.reserve(res.finite_input);
      for (std::size_t i = 0; i < n; ++i)
        if (cloud[i].allFinite()) packed.push_back((key_of(i) << idx_bits) | i);
      radix_sort(packed, idx_bits, key_bits, [](std::uint64_t x) { return x; });
      const std::uint64_t idx_mask = (std::uint64_t{1} << idx_bits) - 1;
      for (std::size_t j = 0; j < packed.size(); ++j) {
        order[j] = static_cast<std::uint32_t>(packed[j] & idx_mask);
        if (j == 0 || (packed[j] >> idx_bits) != (packed[j - 1] >> idx_bits)) run_start.push_back(j);
      }
    } else {
      std::vector<Keyed> keyed;
      keyed.reserve(res.finite_input);
      for (std::size_t i = 0; i < n; ++i)
        if (cloud[i].allFinite()) keyed.push_back({key_of(i), static_cast<std::uint32_t>(i)});
      radix_sort(keyed, 0, key_bits, [](const Keyed& x) { return x.key; });
      for (std::size_t j = 0; j < keyed.size(); ++j) {
        order[j] = keyed[j].index;
        if (j == 0 || keyed[j].key != keyed[j - 1].key) run_start.push_back(j);
      }
    }
  } else {
    // Grids beyond 2^64 cells: sort the (z, y, x) index triples themselves.
    std::vector<std::array<std::int64_t, 3>> zyx(n);
    std::size_t k = 0;
    for (std::size_t i = 0; i < n; ++i) {
      if (!cloud[i].allFinite()) continue;
      zyx[i] = {index_of(i, 2), index_of(i, 1), index_of(i, 0)};
      order[k++] = static_cast<std::uint32_t>(i);
    }
    std::stable_sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) { return zyx[a] < zyx[b]; });
    for (std::size_t j = 0; j < order.size(); ++j)
      if (j == 0 || zyx[order[j]] != zyx[order[j - 1]]) run_start.push_back(j);
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
      const std::uint32_t i = order[k];
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
