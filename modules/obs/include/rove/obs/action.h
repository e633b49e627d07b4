#pragma once
/// \file
/// Action: the run-time polymorphic base of what the robot did between two
/// sensory frames (MRPT's CAction), e.g. RobotMovement2D.

#include <memory>

#include "rove/obs/timestamp.h"
#include "rove/serialization/archive.h"
#include "rove/serialization/serializable.h"

namespace rove {

/// Base of all actions; written and read polymorphically like Observation.
/// Thread-safety: thread-compatible.
class Action : public Serializable {
 public:
  /// When the action ended (the odometry reading's time), if known.
  Timestamp timestamp;

  /// Virtual destructor.
  ~Action() override = default;

  /// A deep copy with the dynamic type of *this.
  virtual std::unique_ptr<Action> clone() const = 0;
  /// True if `other` has the same dynamic type and equal fields.
  virtual bool equals(const Action& other) const = 0;

 protected:
  Action() = default;
  Action(const Action&) = default;
  Action& operator=(const Action&) = default;

  /// Writes the fields above as their own versioned record.
  void save_header(OutArchive& ar) const;
  /// Reads the record save_header wrote.
  void load_header(InArchive& ar);
};

}  // namespace rove
