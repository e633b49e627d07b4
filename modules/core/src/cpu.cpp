#include "rove/core/cpu.h"

#include <atomic>
#include <cstdlib>
#include <cstring>

namespace rove {
namespace {

bool detect_avx2() noexcept {
#if ROVE_AVX2_KERNELS
  // Needed when the first call comes before the runtime's own
  // initialization (from a static initializer); harmless after it.
  __builtin_cpu_init();
  return __builtin_cpu_supports("avx2");
#else
  return false;
#endif
}

bool initial_setting() noexcept {
  if (!detail::cpu_has_avx2()) return false;
  const char* max_isa = std::getenv("ROVE_MAX_ISA");
  return !(max_isa && std::strcmp(max_isa, "sse2") == 0);
}

std::atomic<bool>& setting() noexcept {
  static std::atomic<bool> on{initial_setting()};
  return on;
}

}  // namespace

bool avx2_enabled() noexcept { return setting().load(std::memory_order_relaxed); }

namespace detail {

bool cpu_has_avx2() noexcept {
  static const bool has = detect_avx2();
  return has;
}

void set_avx2_enabled(bool on) noexcept { setting().store(on && cpu_has_avx2(), std::memory_order_relaxed); }

}  // namespace detail
}  // namespace rove
