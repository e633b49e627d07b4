#pragma once
/// \file
/// The error for a request that selects nothing: a range outside a log, a
/// sensor label that is not there, a log without the observations a job
/// needs. Nothing is written; the message says what the input holds.

#include <string>

#include "rove/core/error.h"

namespace rove {

/// The caller asked for something the input does not hold. `option()` names
/// the option that selected nothing ("from_index", "label", ...; empty when
/// the job as a whole found nothing to work on); the message states what
/// was asked and what exists (the log's range, the labels present).
class SelectionError : public Error {
 public:
  SelectionError(std::string option, std::string message)
      : Error(std::move(message)), option_(std::move(option)) {}
  /// The option that selected nothing, as named in the options struct.
  const std::string& option() const noexcept { return option_; }

 private:
  std::string option_;
};

}  // namespace rove
