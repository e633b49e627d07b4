#include "rove/serialization/gzip_stream.h"

#include <zlib.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <limits>
#include <utility>

#include "rove/core/check.h"
#include "rove/core/error.h"

namespace rove {
namespace {

gzFile as_gz(void* f) { return static_cast<gzFile>(f); }

// Largest chunk passed to one gzread/gzwrite call (their length is unsigned
// but their result is an int).
constexpr std::size_t kMaxChunk = std::size_t{1} << 30;

}  // namespace

GzipFileInStream::GzipFileInStream(std::string path) : path_(std::move(path)) {
  errno = 0;
  gzFile f = gzopen(path_.c_str(), "rb");
  if (f == nullptr) {
    throw IoError(path_, std::string("cannot open for reading: ") +
                             (errno != 0 ? std::strerror(errno) : "out of memory"));
  }
  gzbuffer(f, 1u << 17);
  file_ = f;
}

GzipFileInStream::~GzipFileInStream() {
  if (file_ != nullptr) gzclose_r(as_gz(file_));
}

std::size_t GzipFileInStream::read_some(std::span<std::byte> out) {
  std::size_t total = 0;
  while (total < out.size()) {
    const std::size_t want = std::min(out.size() - total, kMaxChunk);
    const int got = gzread(as_gz(file_), out.data() + total, static_cast<unsigned>(want));
    if (got < 0) {
      int code = Z_OK;
      const char* msg = gzerror(as_gz(file_), &code);
      if (code == Z_ERRNO) throw IoError(path_, std::string("read failed: ") + std::strerror(errno));
      throw ParseError({path_, std::nullopt, pos_ + total, "gzip"},
                       std::string("corrupt compressed data: ") + (msg != nullptr ? msg : "?"));
    }
    if (got == 0) {
      // End of the data; a truncated member is reported by zlib as an error
      // on this call or the next one.
      int code = Z_OK;
      const char* msg = gzerror(as_gz(file_), &code);
      if (code != Z_OK) {
        throw ParseError({path_, std::nullopt, pos_ + total, "gzip"},
                         std::string("corrupt compressed data: ") + (msg != nullptr ? msg : "?"));
      }
      break;
    }
    total += static_cast<std::size_t>(got);
  }
  pos_ += total;
  return total;
}

GzipFileOutStream::GzipFileOutStream(std::string path, int level) : path_(std::move(path)) {
  ROVE_CHECK_MSG(level >= 1 && level <= 9, "gzip level must be in 1..9, got {}", level);
  const std::string mode = "wb" + std::to_string(level);
  errno = 0;
  gzFile f = gzopen(path_.c_str(), mode.c_str());
  if (f == nullptr) {
    throw IoError(path_, std::string("cannot open for writing: ") +
                             (errno != 0 ? std::strerror(errno) : "out of memory"));
  }
  gzbuffer(f, 1u << 17);
  file_ = f;
}

GzipFileOutStream::~GzipFileOutStream() {
  if (file_ != nullptr) gzclose_w(as_gz(file_));
}

void GzipFileOutStream::write(std::span<const std::byte> bytes) {
  if (file_ == nullptr) throw IoError(path_, "write after close");
  std::size_t done = 0;
  while (done < bytes.size()) {
    const std::size_t n = std::min(bytes.size() - done, kMaxChunk);
    const int put = gzwrite(as_gz(file_), bytes.data() + done, static_cast<unsigned>(n));
    if (put <= 0) {
      int code = Z_OK;
      const char* msg = gzerror(as_gz(file_), &code);
      throw IoError(path_, std::string("write failed: ") +
                               (code == Z_ERRNO ? std::strerror(errno) : msg));
    }
    done += static_cast<std::size_t>(put);
  }
  pos_ += bytes.size();
}

void GzipFileOutStream::flush() {
  if (file_ == nullptr) throw IoError(path_, "flush after close");
  if (gzflush(as_gz(file_), Z_SYNC_FLUSH) != Z_OK) throw IoError(path_, "flush failed");
}

void GzipFileOutStream::close() {
  if (file_ == nullptr) return;
  const int rc = gzclose_w(as_gz(std::exchange(file_, nullptr)));
  if (rc != Z_OK) throw IoError(path_, "close failed (zlib code " + std::to_string(rc) + ")");
}

}  // namespace rove
