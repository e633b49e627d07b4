#pragma once
// Deserialization of the ROS 1 messages rove reads, from their wire format
// (little-endian fields in definition order; strings and variable arrays
// prefixed by a u32 count), with every length checked against the bytes
// there are. A malformed message throws ParseError naming the field and its
// byte offset within the message.

#include <cstdint>
#include <span>
#include <string>
#include <string_view>

#include "ros_plain.h"

namespace rove::bag_detail {

// The datatypes rove reads, with the MD5 sums of their definitions (those of
// Debian's ros message packages; a test checks them against the headers).
inline constexpr std::string_view kLaserScanType = "sensor_msgs/LaserScan";
inline constexpr std::string_view kLaserScanMd5 = "90c7ef2dc6895d81024acba2ac42f369";
inline constexpr std::string_view kOdometryType = "nav_msgs/Odometry";
inline constexpr std::string_view kOdometryMd5 = "cd5e73d190d741a2f92e81eda573aca7";
inline constexpr std::string_view kPointCloud2Type = "sensor_msgs/PointCloud2";
inline constexpr std::string_view kPointCloud2Md5 = "1158d486dd51d683ce2f1be655c3c181";
inline constexpr std::string_view kImageType = "sensor_msgs/Image";
inline constexpr std::string_view kImageMd5 = "060021388200f6f0f447d0fcd9c64743";
inline constexpr std::string_view kCameraInfoType = "sensor_msgs/CameraInfo";
inline constexpr std::string_view kCameraInfoMd5 = "c9a58c1b0b154e0e6da7578cb991d214";
inline constexpr std::string_view kTfType = "tf2_msgs/TFMessage";
inline constexpr std::string_view kTfMd5 = "94810edda583a504dfda3829e70d7eec";

// `source` names the bag and the message (for errors).
void parse(std::span<const std::uint8_t> bytes, const std::string& source, LaserScanMsg& m);
void parse(std::span<const std::uint8_t> bytes, const std::string& source, OdometryMsg& m);
void parse(std::span<const std::uint8_t> bytes, const std::string& source, PointCloud2Msg& m);
void parse(std::span<const std::uint8_t> bytes, const std::string& source, ImageMsg& m);
void parse(std::span<const std::uint8_t> bytes, const std::string& source, CameraInfoMsg& m);
void parse(std::span<const std::uint8_t> bytes, const std::string& source, TfMsg& m);

}  // namespace rove::bag_detail
