#pragma once
/// \file
/// Values typed on the command line: lists of numbers and poses. One
/// convention for every command (docs/conventions.md, "Poses on the command
/// line"): a pose is "x,y,yaw" or "x,y,z,yaw,pitch,roll", meters and
/// degrees, R = Rz(yaw)·Ry(pitch)·Rx(roll) as MRPT's config files write it;
/// an angle may end in "deg" or "rad" to say its unit.

#include <string_view>
#include <vector>

#include "rove/poses/pose2.h"
#include "rove/poses/pose3.h"

namespace rove::cli {

/// A comma-separated list of finite numbers ("0.25,0.1"; spaces around an
/// item allowed). Throws ParseError naming `option` and the bad item.
std::vector<double> parse_number_list(std::string_view text, std::string_view option);

/// A 3D pose: "x,y,z,yaw,pitch,roll", or "x,y,yaw" for a pose in the plane
/// (z, pitch and roll 0). Angles in degrees unless an item ends in "rad".
/// MRPT's bracketed form "[x y z yaw pitch roll]" is accepted too. Throws
/// ParseError naming `option` on anything else.
Pose3 parse_cli_pose3(std::string_view text, std::string_view option);

/// A 2D pose: "x,y,yaw" (or MRPT's "[x y yaw]"); yaw as in parse_cli_pose3.
Pose2 parse_cli_pose2(std::string_view text, std::string_view option);

/// A 2D position "x,y" (heading 0) or a pose "x,y,yaw" as parse_cli_pose2.
Pose2 parse_cli_position_or_pose2(std::string_view text, std::string_view option);

}  // namespace rove::cli
