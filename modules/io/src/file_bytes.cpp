#include "rove/io/file_bytes.h"

#include "rove/core/files.h"
#include "rove/core/memory_budget.h"

namespace rove {

std::vector<std::uint8_t> read_file_bytes(const std::string& path, std::uint64_t max_bytes,
                                          std::string_view what) {
  const std::string text =
      read_input_file(path, max_bytes == 0 ? memory_budget_bytes() : max_bytes, what);
  return std::vector<std::uint8_t>(text.begin(), text.end());
}

void write_file_bytes(const std::string& path, std::span<const std::uint8_t> bytes) {
  write_text_file_atomically(
      path, std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()));
}

}  // namespace rove
