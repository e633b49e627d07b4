#include "rove/serialization/file_stream.h"

#include <cerrno>
#include <cstring>
#include <utility>

#include "rove/core/error.h"

namespace rove {
namespace {
std::string errno_text(const char* what) {
  return std::string(what) + ": " + std::strerror(errno);
}
}  // namespace

FileInStream::FileInStream(std::string path) : path_(std::move(path)) {
  file_ = std::fopen(path_.c_str(), "rb");
  if (file_ == nullptr) throw IoError(path_, errno_text("cannot open for reading"));
  if (std::fseek(file_, 0, SEEK_END) != 0) {
    std::fclose(file_);
    throw IoError(path_, errno_text("cannot seek"));
  }
  const long end = std::ftell(file_);
  if (end < 0 || std::fseek(file_, 0, SEEK_SET) != 0) {
    std::fclose(file_);
    throw IoError(path_, errno_text("cannot determine the file size"));
  }
  size_ = static_cast<std::uint64_t>(end);
}

FileInStream::~FileInStream() {
  if (file_ != nullptr) std::fclose(file_);
}

std::size_t FileInStream::read_some(std::span<std::byte> out) {
  if (out.empty()) return 0;
  const std::size_t n = std::fread(out.data(), 1, out.size(), file_);
  if (n < out.size() && std::ferror(file_) != 0) {
    throw IoError(path_, errno_text("read failed"));
  }
  pos_ += n;
  return n;
}

std::optional<std::uint64_t> FileInStream::remaining() const {
  return pos_ <= size_ ? size_ - pos_ : 0;
}

FileOutStream::FileOutStream(std::string path) : path_(std::move(path)) {
  file_ = std::fopen(path_.c_str(), "wb");
  if (file_ == nullptr) throw IoError(path_, errno_text("cannot open for writing"));
}

FileOutStream::~FileOutStream() {
  if (file_ != nullptr) std::fclose(file_);
}

void FileOutStream::write(std::span<const std::byte> bytes) {
  if (file_ == nullptr) throw IoError(path_, "write after close");
  if (bytes.empty()) return;
  if (std::fwrite(bytes.data(), 1, bytes.size(), file_) != bytes.size()) {
    throw IoError(path_, errno_text("write failed"));
  }
  pos_ += bytes.size();
}

void FileOutStream::flush() {
  if (file_ == nullptr) throw IoError(path_, "flush after close");
  if (std::fflush(file_) != 0) throw IoError(path_, errno_text("flush failed"));
}

void FileOutStream::close() {
  if (file_ == nullptr) return;
  std::FILE* f = std::exchange(file_, nullptr);
  if (std::fclose(f) != 0) throw IoError(path_, errno_text("close failed"));
}

}  // namespace rove
