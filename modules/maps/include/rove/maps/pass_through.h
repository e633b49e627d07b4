#pragma once
/// \file
/// Pass-through filter (PCL's PassThrough): keeps the points whose chosen
/// field lies within [min, max] (inclusive), or outside it when `negative`.
/// A point whose field is NaN, or whose coordinates are not finite, is
/// removed either way (as PCL does for clouds that are not dense).

#include <cstddef>
#include <limits>
#include <string_view>
#include <vector>

#include "rove/maps/point_cloud.h"

namespace rove {

/// The field a pass-through filter tests.
enum class PointField : std::uint8_t { X, Y, Z, Intensity, NormalX, NormalY, NormalZ };

/// Parses "x", "y", "z", "intensity", "normal_x", "normal_y", "normal_z"
/// (PCL's field names). Throws InvalidArgument for any other name.
PointField parse_point_field(std::string_view name);

/// Options of pass_through_filter (PCL's defaults).
struct PassThroughOptions {
  PointField field = PointField::Z;
  float min = -std::numeric_limits<float>::max();  ///< lower limit (inclusive)
  float max = std::numeric_limits<float>::max();   ///< upper limit (inclusive)
  bool negative = false;  ///< keep the points outside [min, max] instead
};

/// Result of pass_through_filter.
struct PassThroughResult {
  PointCloud cloud;                      ///< the kept points, in input order
  std::vector<std::size_t> kept_indices; ///< their indices in the input
};

/// Filters `cloud`. Preconditions (InvalidArgument): min <= max, neither is
/// NaN; the cloud has the channel the field needs (intensity, normals).
PassThroughResult pass_through_filter(const PointCloud& cloud, const PassThroughOptions& options);

}  // namespace rove
