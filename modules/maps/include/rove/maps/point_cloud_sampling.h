#pragma once
/// \file
/// Down-sampling by selection (no averaging): a random subset of a given
/// size (PCL's RandomSample, small_gicp's random_sampling) and every k-th
/// point (MRPT's decimation).

#include <cstddef>
#include <cstdint>

#include "rove/maps/point_cloud.h"

namespace rove {

/// `count` points drawn uniformly without replacement (all of them if the
/// cloud has no more), kept in input order. Deterministic for a given seed.
PointCloud random_downsample(const PointCloud& cloud, std::size_t count, std::uint64_t seed = 0);

/// Points 0, step, 2·step, ... Precondition (InvalidArgument): step >= 1.
PointCloud uniform_downsample(const PointCloud& cloud, std::size_t step);

}  // namespace rove
