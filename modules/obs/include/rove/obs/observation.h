#pragma once
/// \file
/// Observation: the run-time polymorphic base of every sensor reading (the
/// concrete kind is only known when a log is read). Each observation carries
/// when it was taken, which sensor took it, and where that sensor sits on
/// the robot.

#include <memory>
#include <string>
#include <string_view>

#include "rove/obs/timestamp.h"
#include "rove/poses/pose3.h"
#include "rove/serialization/archive.h"
#include "rove/serialization/serializable.h"

namespace rove {

/// Base of all observations. Concrete classes are plain data records with
/// public fields; they are written and read polymorphically through
/// rove::write_object / rove::read_object (see register_obs_classes).
/// Thread-safety: thread-compatible (const members may run concurrently).
class Observation : public Serializable {
 public:
  /// When the reading was taken.
  Timestamp timestamp;
  /// Name of the sensor that produced it, e.g. "LASER_FRONT" (free text).
  std::string sensor_label;
  /// T_robot_sensor: pose of the sensor frame in the robot frame (meters,
  /// radians), MRPT's `sensorPose`. Each observation type documents its
  /// sensor frame's axes.
  Pose3 T_robot_sensor;

  /// Virtual destructor.
  ~Observation() override = default;

  /// A deep copy with the dynamic type of *this.
  virtual std::unique_ptr<Observation> clone() const = 0;
  /// True if `other` has the same dynamic type and equal fields (exact
  /// floating-point equality; NaN never equals NaN).
  virtual bool equals(const Observation& other) const = 0;

 protected:
  Observation() = default;
  Observation(const Observation&) = default;
  Observation& operator=(const Observation&) = default;

  /// Compares the fields above (not the dynamic type).
  bool header_equals(const Observation& other) const;
  /// Writes the fields above as their own versioned record.
  void save_header(OutArchive& ar) const;
  /// Reads the record save_header wrote. Throws ParseError on malformed
  /// data (including a stored rotation that is not orthonormal).
  void load_header(InArchive& ar);
};

/// The base of each concrete observation type: implements the members that
/// every type defines the same way, from `Derived::kClassName` (the stored
/// class name) and Derived's operator== (exact equality of every field).
/// Usage: `class RangeScan2D final : public ObservationOf<RangeScan2D>`.
template <typename Derived>
class ObservationOf : public Observation {
 public:
  /// The stored class name (Derived::kClassName).
  std::string_view class_name() const override { return Derived::kClassName; }
  /// A deep copy.
  std::unique_ptr<Observation> clone() const override {
    return std::make_unique<Derived>(static_cast<const Derived&>(*this));
  }
  /// Same dynamic type and Derived's operator==.
  bool equals(const Observation& other) const override {
    const auto* o = dynamic_cast<const Derived*>(&other);
    return o != nullptr && static_cast<const Derived&>(*this) == *o;
  }

 protected:
  ObservationOf() = default;
  ObservationOf(const ObservationOf&) = default;
  ObservationOf& operator=(const ObservationOf&) = default;
};

}  // namespace rove
