#pragma once
/// \file
/// A stated memory budget, checked before large allocations whose size comes
/// from outside (a grid's resolution and extent, an image's width × height, a
/// count read from a file). The budget is the smaller of 75 % of the machine's
/// physical memory and the address-space limit (ulimit -v), unless the
/// environment variable ROVE_MEMORY_BUDGET sets it ("512M", "8G", bytes).

#include <cstdint>
#include <string>
#include <string_view>

namespace rove {

/// Thrown when a requested allocation exceeds the budget. Names what asked.
class ResourceError;

/// The budget in bytes (read once from the environment and the machine).
std::uint64_t memory_budget_bytes();

/// Throws rove::ResourceError when `bytes` exceed the budget. `what` names the
/// file, key or option responsible, e.g. "[MappingApplication] resolution=0.001
/// gives a 40000 × 40000 grid".
void check_memory_budget(std::uint64_t bytes, std::string_view what);

/// `n` × `bytes_each`, saturating at UINT64_MAX instead of overflowing.
std::uint64_t checked_bytes(std::uint64_t n, std::uint64_t bytes_each) noexcept;

/// "6.3 GB", "512 MB", "12 kB".
std::string format_bytes(std::uint64_t bytes);

}  // namespace rove
