#include "rove/core/check.h"

namespace rove::detail {

void check_failed(const char* expression, const std::string& detail, SourceFrame where) {
  std::string msg = fmt::format("check failed: {}", expression);
  if (!detail.empty()) msg += fmt::format(" ({})", detail);
  throw InvalidArgument(std::move(msg), std::move(where));
}

}  // namespace rove::detail
