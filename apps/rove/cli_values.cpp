#include "cli_values.h"

#include <fmt/format.h>

#include <cctype>
#include <cmath>
#include <numbers>
#include <optional>
#include <string>

#include "rove/core/error.h"
#include "rove/core/files.h"

namespace rove::cli {

namespace {

ParseError value_error(std::string_view option, const std::string& message) {
  return ParseError({std::string(option), std::nullopt, std::nullopt, "value"}, message);
}

std::string_view trim(std::string_view s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
  return s;
}

bool ends_with(std::string_view s, std::string_view suffix) {
  return s.size() >= suffix.size() && s.substr(s.size() - suffix.size()) == suffix;
}

/// The whole item as one finite number, or nullopt.
std::optional<double> to_number(std::string_view item) {
  item = trim(item);
  if (item.empty()) return std::nullopt;
  const std::string s(item);
  std::size_t used = 0;
  double x = 0;
  try {
    x = std::stod(s, &used);
  } catch (const std::exception&) {
    return std::nullopt;
  }
  if (used != s.size() || !std::isfinite(x)) return std::nullopt;
  return x;
}

/// The items of a pose: split at commas, or at spaces inside MRPT's brackets.
std::vector<std::string_view> pose_items(std::string_view text) {
  text = trim(text);
  char separator = ',';
  if (text.size() >= 2 && text.front() == '[' && text.back() == ']') {
    text = text.substr(1, text.size() - 2);
    separator = ' ';
  }
  std::vector<std::string_view> items;
  std::size_t start = 0;
  while (start <= text.size()) {
    std::size_t end = text.find(separator, start);
    if (end == std::string_view::npos) end = text.size();
    const std::string_view item = trim(text.substr(start, end - start));
    if (!(separator == ' ' && item.empty())) items.push_back(item);
    start = end + 1;
  }
  return items;
}

/// Parses each item of a pose, angles returned in radians: the last three of
/// six items (yaw, pitch, roll), else the items from the third on (yaw).
/// Angles are in degrees unless suffixed "rad".
std::vector<double> pose_values(std::string_view text, std::string_view option) {
  const std::vector<std::string_view> items = pose_items(text);
  const std::size_t first_angle = items.size() == 6 ? 3 : 2;
  std::vector<double> v;
  for (std::size_t i = 0; i < items.size(); ++i) {
    std::string_view item = items[i];
    double scale = 1.0;
    if (i >= first_angle) {
      scale = std::numbers::pi / 180.0;
      if (ends_with(item, "rad")) {
        item.remove_suffix(3);
        scale = 1.0;
      } else if (ends_with(item, "deg")) {
        item.remove_suffix(3);
      }
    }
    const std::optional<double> x = to_number(item);
    if (!x)
      throw value_error(option, fmt::format("'{}' (item {}) is not a finite number",
                                            printable(items[i]), i + 1));
    v.push_back(*x * scale);
  }
  return v;
}

}  // namespace

std::vector<double> parse_number_list(std::string_view text, std::string_view option) {
  std::vector<double> v;
  std::size_t start = 0;
  while (start <= text.size()) {
    std::size_t end = text.find(',', start);
    if (end == std::string_view::npos) end = text.size();
    const std::string_view item = text.substr(start, end - start);
    const std::optional<double> x = to_number(item);
    if (!x)
      throw value_error(option, fmt::format("'{}' is not a finite number", printable(item)));
    v.push_back(*x);
    start = end + 1;
  }
  return v;
}

Pose3 parse_cli_pose3(std::string_view text, std::string_view option) {
  const std::vector<double> v = pose_values(text, option);
  if (v.size() == 6) return Pose3(v[0], v[1], v[2], v[3], v[4], v[5]);
  if (v.size() == 3) return Pose3(v[0], v[1], 0.0, v[2], 0.0, 0.0);
  throw value_error(option, fmt::format("expected x,y,z,yaw,pitch,roll or x,y,yaw (meters, "
                                        "degrees), got {} values",
                                        v.size()));
}

Pose2 parse_cli_pose2(std::string_view text, std::string_view option) {
  const std::vector<double> v = pose_values(text, option);
  if (v.size() == 3) return Pose2(v[0], v[1], v[2]);
  throw value_error(option,
                    fmt::format("expected x,y,yaw (meters, degrees), got {} values", v.size()));
}

Pose2 parse_cli_position_or_pose2(std::string_view text, std::string_view option) {
  const std::vector<double> v = pose_values(text, option);
  if (v.size() == 2) return Pose2(v[0], v[1], 0.0);
  if (v.size() == 3) return Pose2(v[0], v[1], v[2]);
  throw value_error(option, fmt::format("expected x,y or x,y,yaw (meters, degrees), got {} values",
                                        v.size()));
}

}  // namespace rove::cli
