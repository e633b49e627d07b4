#include "rove/core/parallel.h"

#include <fmt/format.h>

#include <thread>

#include "rove/core/error.h"

namespace rove {

int resolve_thread_count(int requested, const char* what) {
  if (requested == 0) {
    const unsigned hw = std::thread::hardware_concurrency();
    return hw == 0 ? 1 : static_cast<int>(std::min<unsigned>(hw, kMaxThreads));
  }
  if (requested < 0 || requested > kMaxThreads) {
    throw InvalidArgument(fmt::format("{} = {}: use 1 to {} threads, or 0 for all hardware threads",
                                      what, requested, kMaxThreads));
  }
  return requested;
}

}  // namespace rove
