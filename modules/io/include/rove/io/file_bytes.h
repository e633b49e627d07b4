#pragma once
/// \file
/// Whole files as bytes, for the readers and writers of binary formats that
/// decode from and encode to memory (images, PCD, PLY).

#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace rove {

/// Reads a whole input file into memory: a regular file (a directory, a
/// device or a FIFO is refused) of at most `max_bytes` (the memory budget by
/// default); `what` names the file's role in messages. Throws IoError naming
/// the path.
std::vector<std::uint8_t> read_file_bytes(const std::string& path, std::uint64_t max_bytes = 0,
                                          std::string_view what = "input file");
/// Writes bytes to a file atomically (rove/core/files.h). Throws IoError
/// naming the path.
void write_file_bytes(const std::string& path, std::span<const std::uint8_t> bytes);

}  // namespace rove
