#pragma once
// What a log held, for the errors of the runs over logs (icp_slam_run.cpp,
// lidar_slam_run.cpp): "3 RangeScan2D, 2 OdometryObservation".

#include <cstdint>
#include <map>
#include <string>

#include <fmt/format.h>

namespace rove::detail {

/// "n Class, m Other" in class-name order, or "nothing".
inline std::string describe_counts(const std::map<std::string, std::uint64_t>& counts) {
  std::string d;
  for (const auto& [name, n] : counts) {
    if (!d.empty()) d += ", ";
    d += fmt::format("{} {}", n, name);
  }
  return d.empty() ? "nothing" : d;
}

}  // namespace rove::detail
