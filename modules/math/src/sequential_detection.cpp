#include "rove/math/sequential_detection.h"

namespace rove {

std::string_view to_string(DetectionTermination t) {
  switch (t) {
    case DetectionTermination::MaxModels: return "MaxModels";
    case DetectionTermination::TooFewData: return "TooFewData";
    case DetectionTermination::NoSupportedModel: return "NoSupportedModel";
  }
  ROVE_CHECK_MSG(false, "invalid DetectionTermination value {}", static_cast<int>(t));
  return {};
}

}  // namespace rove
