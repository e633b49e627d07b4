#include "carmen_input.h"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <utility>

#include "rove/core/error.h"

namespace rove::detail {
namespace {
constexpr std::size_t kChunk = std::size_t{1} << 16;
}  // namespace

CarmenRawSource CarmenRawSource::file(const std::string& path) {
  CarmenRawSource s;
  s.file_ = std::fopen(path.c_str(), "rb");
  if (s.file_ == nullptr) {
    throw IoError(path, std::string("cannot open: ") + std::strerror(errno));
  }
  return s;
}

CarmenRawSource CarmenRawSource::memory(std::string bytes) {
  CarmenRawSource s;
  s.memory_ = std::move(bytes);
  return s;
}

CarmenRawSource::CarmenRawSource(CarmenRawSource&& other) noexcept
    : file_(std::exchange(other.file_, nullptr)),
      memory_(std::move(other.memory_)),
      memory_pos_(other.memory_pos_) {}

CarmenRawSource::~CarmenRawSource() {
  if (file_ != nullptr) std::fclose(file_);
}

std::size_t CarmenRawSource::read(char* out, std::size_t capacity, const std::string& name) {
  if (file_ != nullptr) {
    const std::size_t n = std::fread(out, 1, capacity, file_);
    if (n < capacity && std::ferror(file_) != 0) throw IoError(name, "read failed");
    return n;
  }
  const std::size_t n = std::min(capacity, memory_.size() - memory_pos_);
  if (n > 0) std::memcpy(out, memory_.data() + memory_pos_, n);
  memory_pos_ += n;
  return n;
}

CarmenByteStream::CarmenByteStream(CarmenRawSource source, std::string name)
    : source_(std::move(source)), name_(std::move(name)), raw_(kChunk) {
  // Detect the magic: read until at least 3 bytes or the end.
  while (raw_end_ < 3 && refill_raw()) {
  }
  compressed_ = raw_end_ >= 3 && raw_[0] == 'B' && raw_[1] == 'Z' && raw_[2] == 'h';
}

CarmenByteStream::~CarmenByteStream() {
  if (bz_active_) BZ2_bzDecompressEnd(&bz_);
}

bool CarmenByteStream::refill_raw() {
  if (raw_eof_) return false;
  if (raw_begin_ > 0) {
    std::memmove(raw_.data(), raw_.data() + raw_begin_, raw_end_ - raw_begin_);
    raw_end_ -= raw_begin_;
    raw_begin_ = 0;
  }
  if (raw_end_ == raw_.size()) return true;
  const std::size_t n = source_.read(raw_.data() + raw_end_, raw_.size() - raw_end_, name_);
  if (n == 0) {
    raw_eof_ = true;
    return false;
  }
  raw_end_ += n;
  return true;
}

void CarmenByteStream::fail(const std::string& problem) const {
  ParseError::Location where;
  where.source = name_;
  where.offset = raw_consumed_;
  where.field = "bzip2";
  throw ParseError(std::move(where), problem);
}

std::size_t CarmenByteStream::read(char* out, std::size_t capacity) {
  if (finished_ || capacity == 0) return 0;
  if (!compressed_) {
    if (raw_begin_ == raw_end_ && !refill_raw()) {
      finished_ = true;
      return 0;
    }
    const std::size_t n = std::min(capacity, raw_end_ - raw_begin_);
    std::memcpy(out, raw_.data() + raw_begin_, n);
    raw_begin_ += n;
    return n;
  }
  for (;;) {
    if (!bz_active_) {
      // A new stream starts here (the first, or one concatenated after a
      // finished stream, as pbzip2 writes). Anything else ends the input.
      if (raw_begin_ == raw_end_ && !refill_raw()) {
        finished_ = true;
        return 0;
      }
      while (raw_end_ - raw_begin_ < 3 && refill_raw()) {
      }
      const char* p = raw_.data() + raw_begin_;
      if (raw_end_ - raw_begin_ < 3 || p[0] != 'B' || p[1] != 'Z' || p[2] != 'h') {
        fail("data after the end of the bzip2 stream is not another bzip2 stream");
      }
      bz_ = bz_stream{};
      if (BZ2_bzDecompressInit(&bz_, 0, 0) != BZ_OK) fail("cannot initialize bzip2");
      bz_active_ = true;
    }
    if (raw_begin_ == raw_end_ && !refill_raw()) fail("truncated bzip2 stream");
    bz_.next_in = raw_.data() + raw_begin_;
    bz_.avail_in = static_cast<unsigned>(raw_end_ - raw_begin_);
    bz_.next_out = out;
    bz_.avail_out = static_cast<unsigned>(std::min<std::size_t>(capacity, 1u << 30));
    const int rc = BZ2_bzDecompress(&bz_);
    const std::size_t used = (raw_end_ - raw_begin_) - bz_.avail_in;
    raw_begin_ += used;
    raw_consumed_ += used;
    const std::size_t produced = std::min<std::size_t>(capacity, 1u << 30) - bz_.avail_out;
    if (rc == BZ_STREAM_END) {
      BZ2_bzDecompressEnd(&bz_);
      bz_active_ = false;
    } else if (rc != BZ_OK) {
      fail("corrupt bzip2 data (libbz2 error " + std::to_string(rc) + ")");
    }
    if (produced > 0) return produced;
  }
}

CarmenLineReader::CarmenLineReader(CarmenRawSource source, std::string name,
                                   std::size_t max_line_bytes)
    : bytes_(std::move(source), std::move(name)), max_line_bytes_(max_line_bytes), buf_(kChunk) {}

bool CarmenLineReader::fill() {
  if (eof_) return false;
  if (begin_ == end_) begin_ = end_ = 0;
  const std::size_t n = bytes_.read(buf_.data() + end_, buf_.size() - end_);
  if (n == 0) {
    eof_ = true;
    return false;
  }
  end_ += n;
  return true;
}

bool CarmenLineReader::next(std::string& line, bool& too_long) {
  line.clear();
  too_long = false;
  bool any = false;
  for (;;) {
    if (begin_ == end_) {
      begin_ = end_ = 0;
      if (!fill()) break;
    }
    any = true;
    const char* start = buf_.data() + begin_;
    const void* nl = std::memchr(start, '\n', end_ - begin_);
    const std::size_t len =
        nl != nullptr ? static_cast<std::size_t>(static_cast<const char*>(nl) - start) : end_ - begin_;
    const std::size_t room = line.size() < max_line_bytes_ ? max_line_bytes_ - line.size() : 0;
    if (len > room) too_long = true;
    line.append(start, std::min(len, room));
    begin_ += len;
    if (nl != nullptr) {
      ++begin_;  // the '\n'
      break;
    }
  }
  if (!any) return false;
  if (!line.empty() && line.back() == '\r') line.pop_back();
  return true;
}

}  // namespace rove::detail
