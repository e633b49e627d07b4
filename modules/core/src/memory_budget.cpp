#include "rove/core/memory_budget.h"

#include <fmt/format.h>
#include <sys/resource.h>
#include <unistd.h>

#include <cctype>
#include <cstdlib>
#include <limits>

#include "rove/core/error.h"

namespace rove {
namespace {

constexpr std::uint64_t kUnlimited = std::numeric_limits<std::uint64_t>::max();

// "512M", "8G", "1.5G", "123456" → bytes; 0 when malformed.
std::uint64_t parse_size(const char* text) {
  char* end = nullptr;
  const double v = std::strtod(text, &end);
  if (end == text || !(v > 0)) return 0;
  double scale = 1;
  switch (std::toupper(static_cast<unsigned char>(*end))) {
    case 'K': scale = 1024.0; ++end; break;
    case 'M': scale = 1024.0 * 1024; ++end; break;
    case 'G': scale = 1024.0 * 1024 * 1024; ++end; break;
    case 'T': scale = 1024.0 * 1024 * 1024 * 1024; ++end; break;
    default: break;
  }
  if (*end == 'B' || *end == 'b') ++end;
  if (*end != '\0') return 0;
  const double bytes = v * scale;
  return bytes >= 1.8e19 ? kUnlimited : static_cast<std::uint64_t>(bytes);
}

std::uint64_t compute_budget() {
  if (const char* env = std::getenv("ROVE_MEMORY_BUDGET")) {
    const std::uint64_t b = parse_size(env);
    if (b == 0) {
      throw ConfigError("ROVE_MEMORY_BUDGET", "environment", "ROVE_MEMORY_BUDGET",
                        fmt::format("'{}' is not a size (e.g. 512M, 8G)", env));
    }
    return b;
  }
  std::uint64_t budget = kUnlimited;
  const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGESIZE);
  if (pages > 0 && page > 0) {
    budget = static_cast<std::uint64_t>(pages) / 4 * 3 * static_cast<std::uint64_t>(page);
  }
  rlimit as{};
  if (getrlimit(RLIMIT_AS, &as) == 0 && as.rlim_cur != RLIM_INFINITY) {
    budget = std::min<std::uint64_t>(budget, static_cast<std::uint64_t>(as.rlim_cur) / 4 * 3);
  }
  return budget;
}

}  // namespace

std::uint64_t memory_budget_bytes() {
  static const std::uint64_t budget = compute_budget();
  return budget;
}

std::uint64_t checked_bytes(std::uint64_t n, std::uint64_t bytes_each) noexcept {
  if (bytes_each != 0 && n > kUnlimited / bytes_each) return kUnlimited;
  return n * bytes_each;
}

std::string format_bytes(std::uint64_t bytes) {
  const double b = static_cast<double>(bytes);
  if (bytes == kUnlimited) return "more than 16 EB";
  if (b >= 1e9) return fmt::format("{:.1f} GB", b / 1e9);
  if (b >= 1e6) return fmt::format("{:.1f} MB", b / 1e6);
  if (b >= 1e3) return fmt::format("{:.1f} kB", b / 1e3);
  return fmt::format("{} B", bytes);
}

void check_memory_budget(std::uint64_t bytes, std::string_view what) {
  const std::uint64_t budget = memory_budget_bytes();
  if (bytes > budget) {
    throw ResourceError(fmt::format(
        "{} needs {}, over rove's memory budget of {} (75 % of physical memory or the "
        "ulimit -v; set ROVE_MEMORY_BUDGET to change it)",
        what, format_bytes(bytes), format_bytes(budget)));
  }
}

}  // namespace rove
