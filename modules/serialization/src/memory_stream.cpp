#include "rove/serialization/memory_stream.h"

#include <algorithm>
#include <cstring>
#include <utility>

namespace rove {

MemoryInStream::MemoryInStream(std::span<const std::byte> data, std::string name)
    : view_(data), name_(std::move(name)) {}

MemoryInStream::MemoryInStream(std::vector<std::byte> data, std::string name)
    : owned_(std::move(data)), view_(owned_), name_(std::move(name)) {}

std::size_t MemoryInStream::read_some(std::span<std::byte> out) {
  const std::size_t n = std::min(out.size(), view_.size() - pos_);
  if (n > 0) std::memcpy(out.data(), view_.data() + pos_, n);
  pos_ += n;
  return n;
}

MemoryOutStream::MemoryOutStream(std::string name) : name_(std::move(name)) {}

void MemoryOutStream::write(std::span<const std::byte> bytes) {
  data_.insert(data_.end(), bytes.begin(), bytes.end());
}

std::vector<std::byte> MemoryOutStream::take() noexcept {
  std::vector<std::byte> out;
  out.swap(data_);
  return out;
}

}  // namespace rove
