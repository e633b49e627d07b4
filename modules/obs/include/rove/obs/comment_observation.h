#pragma once
/// \file
/// CommentObservation: free text stored in a log (MRPT's
/// CObservationComment), e.g. a dataset's description or calibration notes.

#include <memory>
#include <string>
#include <string_view>

#include "rove/obs/observation.h"

namespace rove {

/// A text note with a timestamp; no sensor data.
class CommentObservation final : public ObservationOf<CommentObservation> {
 public:
  /// Stored class name: "CommentObservation".
  static constexpr std::string_view kClassName = "CommentObservation";

  /// The text, as stored (any bytes; usually UTF-8 or ASCII).
  std::string text;

  /// An empty comment.
  CommentObservation() = default;

  /// Exact equality of every field.
  friend bool operator==(const CommentObservation& a, const CommentObservation& b);

  /// The newest record version this build writes.
  std::uint8_t version() const override { return 1; }
  /// Writes the fields (Serializable contract).
  void save_payload(OutArchive& ar) const override;
  /// Reads fields written by save_payload; ParseError on malformed data.
  void load_payload(InArchive& ar, std::uint8_t version) override;
};

}  // namespace rove
