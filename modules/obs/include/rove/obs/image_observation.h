#pragma once
/// \file
/// ImageObservation: one camera image with its intrinsics (MRPT's
/// CObservationImage). T_robot_sensor is the pose of the camera's optical
/// frame (z forward, x right, y down) on the robot.

#include <cstdint>
#include <memory>
#include <string_view>

#include "rove/obs/image.h"
#include "rove/obs/observation.h"
#include "rove/obs/pinhole_camera.h"

namespace rove {

/// A camera image and its intrinsics.
class ImageObservation final : public ObservationOf<ImageObservation> {
 public:
  /// Stored class name: "ImageObservation".
  static constexpr std::string_view kClassName = "ImageObservation";

  /// Intrinsics of the camera that took the image.
  PinholeCamera camera;
  /// The image.
  Image image;

  /// An empty image.
  ImageObservation() = default;

  /// Throws InvalidArgument unless the image passes its check and, when
  /// the camera has a size, it equals the image's.
  void check() const;

  /// Exact equality of every field.
  friend bool operator==(const ImageObservation& a, const ImageObservation& b);

  /// The newest record version this build writes.
  std::uint8_t version() const override { return 1; }
  /// Writes the fields (Serializable contract).
  void save_payload(OutArchive& ar) const override;
  /// Reads fields written by save_payload; ParseError on malformed data.
  void load_payload(InArchive& ar, std::uint8_t version) override;
};

}  // namespace rove
