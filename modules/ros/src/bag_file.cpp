#include "bag_file.h"

#include <bzlib.h>
#include <fmt/format.h>
#include <roslz4/lz4s.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <string_view>

#include "rove/core/error.h"
#include "rove/core/files.h"
#include "rove/core/memory_budget.h"

namespace rove::bag_detail {
namespace {

constexpr std::string_view kMagic = "#ROSBAG V2.0\n";
// A record header holds a few short fields (op, conn, topic, time,
// compression, size, index_pos ...); anything larger is not a bag.
constexpr std::uint32_t kMaxRecordHeader = 1u << 20;

constexpr std::uint8_t kOpMessage = 0x02;
constexpr std::uint8_t kOpBagHeader = 0x03;
constexpr std::uint8_t kOpIndex = 0x04;
constexpr std::uint8_t kOpChunk = 0x05;
constexpr std::uint8_t kOpChunkInfo = 0x06;
constexpr std::uint8_t kOpConnection = 0x07;

std::uint32_t le32(const std::uint8_t* p) {
  return std::uint32_t{p[0]} | std::uint32_t{p[1]} << 8 | std::uint32_t{p[2]} << 16 |
         std::uint32_t{p[3]} << 24;
}

// The fields of a record header ("name=value", each after a u32 length), or
// an error message.
struct Fields {
  std::map<std::string, std::span<const std::uint8_t>, std::less<>> values;
  std::string error;

  std::optional<std::uint32_t> u32(std::string_view name) const {
    auto it = values.find(name);
    if (it == values.end() || it->second.size() != 4) return std::nullopt;
    return le32(it->second.data());
  }
  std::optional<std::uint64_t> u64(std::string_view name) const {
    auto it = values.find(name);
    if (it == values.end() || it->second.size() != 8) return std::nullopt;
    return std::uint64_t{le32(it->second.data())} |
           std::uint64_t{le32(it->second.data() + 4)} << 32;
  }
  std::optional<std::string> str(std::string_view name) const {
    auto it = values.find(name);
    if (it == values.end()) return std::nullopt;
    return std::string(reinterpret_cast<const char*>(it->second.data()), it->second.size());
  }
  std::optional<std::uint8_t> op() const {
    auto it = values.find("op");
    if (it == values.end() || it->second.size() != 1) return std::nullopt;
    return it->second[0];
  }
};

Fields parse_fields(std::span<const std::uint8_t> h) {
  Fields f;
  std::size_t at = 0;
  while (at < h.size()) {
    if (h.size() - at < 4) {
      f.error = fmt::format("header field length cut off at byte {} of the header", at);
      return f;
    }
    const std::uint32_t len = le32(h.data() + at);
    at += 4;
    if (len > h.size() - at) {
      f.error = fmt::format("header field of {} bytes at byte {} runs past the header's {} bytes",
                            len, at - 4, h.size());
      return f;
    }
    const auto field = h.subspan(at, len);
    const auto eq = std::find(field.begin(), field.end(), std::uint8_t{'='});
    if (eq == field.end()) {
      f.error = fmt::format("header field at byte {} has no '='", at - 4);
      return f;
    }
    const auto name_len = static_cast<std::size_t>(eq - field.begin());
    f.values.emplace(std::string(reinterpret_cast<const char*>(field.data()), name_len),
                     field.subspan(name_len + 1));
    at += len;
  }
  return f;
}

// Output of a decompression: grown as data arrives (up to the size the
// chunk declares), so a chunk that claims gigabytes costs only what it
// really holds.
class Growing {
 public:
  Growing(std::vector<std::uint8_t>& out, std::size_t declared) : out_(out), declared_(declared) {
    out_.resize(std::min<std::size_t>(declared_, kStep));
  }
  // Room after `produced` bytes; false when the declared size is reached.
  bool grow(std::size_t produced) {
    if (produced < out_.size()) return true;
    if (out_.size() >= declared_) return false;
    out_.resize(std::min(declared_, out_.size() + std::max(kStep, out_.size())));
    return true;
  }
  std::uint8_t* at(std::size_t produced) { return out_.data() + produced; }
  std::size_t room(std::size_t produced) const { return out_.size() - produced; }

 private:
  static constexpr std::size_t kStep = std::size_t{1} << 20;
  std::vector<std::uint8_t>& out_;
  std::size_t declared_;
};

// Decompresses as much of `in` as it can into `out` (at most `declared`
// bytes); returns the bytes produced and, through `error`, what went wrong
// (empty if the stream ended well).
std::size_t bunzip2(std::span<const std::uint8_t> in, std::vector<std::uint8_t>& out,
                    std::size_t declared, std::string& error) {
  bz_stream s{};
  if (BZ2_bzDecompressInit(&s, 0, 0) != BZ_OK) {
    error = "bzip2: cannot initialize";
    return 0;
  }
  Growing buf(out, declared);
  std::size_t produced = 0;
  s.next_in = const_cast<char*>(reinterpret_cast<const char*>(in.data()));
  s.avail_in = static_cast<unsigned>(in.size());
  int ret = BZ_OK;
  while (buf.grow(produced)) {
    s.next_out = reinterpret_cast<char*>(buf.at(produced));
    s.avail_out = static_cast<unsigned>(buf.room(produced));
    const unsigned before_in = s.avail_in, before_out = s.avail_out;
    ret = BZ2_bzDecompress(&s);
    produced += before_out - s.avail_out;
    if (ret != BZ_OK) break;
    if (s.avail_in == before_in && s.avail_out == before_out) break;  // needs more input
  }
  if (ret != BZ_STREAM_END) {
    error = ret == BZ_OK ? "bzip2 data ends before its end-of-stream marker"
                         : fmt::format("bzip2 data is corrupt (error {})", ret);
  }
  BZ2_bzDecompressEnd(&s);
  return produced;
}

// lz4 expands data at most 255-fold; roslz4 needs the whole output buffer
// up front, so a chunk that declares more than that is refused before it
// is allocated.
std::size_t unlz4(std::span<const std::uint8_t> in, std::vector<std::uint8_t>& out,
                  std::size_t declared, std::string& error) {
  if (declared > 255 * in.size() + 65536) {
    error = fmt::format("declares {} bytes from {} compressed bytes, more than lz4 can expand",
                        declared, in.size());
    return 0;
  }
  out.resize(declared);
  roslz4_stream s{};
  s.input_next = const_cast<char*>(reinterpret_cast<const char*>(in.data()));
  s.input_left = static_cast<int>(in.size());
  s.output_next = reinterpret_cast<char*>(out.data());
  s.output_left = static_cast<int>(out.size());
  if (roslz4_decompressStart(&s) != ROSLZ4_OK) {
    error = "lz4: cannot initialize";
    return 0;
  }
  int ret = ROSLZ4_OK;
  while (true) {
    const int before_in = s.input_left, before_out = s.output_left;
    ret = roslz4_decompress(&s);
    if (ret != ROSLZ4_OK) break;
    if (s.input_left == before_in && s.output_left == before_out) break;  // needs more input
  }
  const std::size_t produced = out.size() - static_cast<std::size_t>(s.output_left);
  if (ret != ROSLZ4_STREAM_END) {
    error = ret == ROSLZ4_OK ? "lz4 data ends before its end of frame"
                             : fmt::format("lz4 data is corrupt (error {})", ret);
  }
  roslz4_decompressEnd(&s);
  return produced;
}

}  // namespace

BagFile::BagFile(const std::string& path) : path_(path) {
  check_regular_input(path, "ROS bag");
  in_.open(path, std::ios::binary);
  if (!in_) throw IoError(path, "cannot open the ROS bag");
  size_ = std::filesystem::file_size(path);
  std::string magic(kMagic.size(), '\0');
  in_.read(magic.data(), static_cast<std::streamsize>(magic.size()));
  if (!in_ || magic != kMagic) {
    throw ParseError({path, std::nullopt, 0, "format"},
                     "not a ROS bag of format 2.0 (no \"#ROSBAG V2.0\" line)");
  }
  offset_ = kMagic.size();
  // The bag header record comes first.
  if (!read_record()) {
    throw ParseError({path, std::nullopt, offset_, "bag header"},
                     stats_.stop_reason.empty() ? "no bag header record" : stats_.stop_reason);
  }
}

void BagFile::stop(std::uint64_t at, std::string reason) {
  if (!stats_.stopped_at) {
    stats_.stopped_at = at;
    stats_.stop_reason = std::move(reason);
  }
  done_ = true;
}

void BagFile::add_connection(std::uint32_t id, const std::string& topic,
                             std::span<const std::uint8_t> data) {
  if (connections_.contains(id)) return;  // repeated in the index section
  const Fields f = parse_fields(data);
  BagConnection c;
  c.id = id;
  // The record header names the topic; the connection header may repeat it.
  c.topic = topic.empty() ? f.str("topic").value_or("") : topic;
  c.datatype = f.str("type").value_or("");
  c.md5sum = f.str("md5sum").value_or("");
  connections_.emplace(id, std::move(c));
}

void BagFile::parse_chunk_records(std::size_t valid_bytes, std::uint64_t chunk_offset) {
  pending_.clear();
  next_pending_ = 0;
  std::size_t at = 0;
  const std::span<const std::uint8_t> bytes(chunk_.data(), valid_bytes);
  while (at < valid_bytes) {
    if (valid_bytes - at < 4) break;
    const std::uint32_t hlen = le32(bytes.data() + at);
    if (hlen > valid_bytes - at - 4 || valid_bytes - at - 4 - hlen < 4) break;
    const Fields f = parse_fields(bytes.subspan(at + 4, hlen));
    const std::uint32_t dlen = le32(bytes.data() + at + 4 + hlen);
    const std::size_t data_at = at + 8 + hlen;
    if (dlen > valid_bytes - data_at) break;
    if (!f.error.empty() || !f.op()) {
      stop(chunk_offset, fmt::format("malformed record at byte {} inside the chunk: {}", at,
                                     f.error.empty() ? "no op field" : f.error));
      return;
    }
    const auto op = *f.op();
    if (op == kOpConnection) {
      if (auto id = f.u32("conn")) {
        add_connection(*id, f.str("topic").value_or(""), bytes.subspan(data_at, dlen));
      }
    } else if (op == kOpMessage) {
      const auto conn = f.u32("conn");
      const auto time = f.u64("time");
      if (!conn || !time) {
        stop(chunk_offset, fmt::format("message record at byte {} inside the chunk lacks its "
                                       "conn or time field", at));
        return;
      }
      pending_.push_back({*conn, static_cast<std::uint32_t>(*time & 0xffffffffu),
                          static_cast<std::uint32_t>(*time >> 32), data_at, dlen});
    } else {
      ++stats_.unknown_records;
    }
    at = data_at + dlen;
  }
  std::stable_sort(pending_.begin(), pending_.end(), [](const Pending& a, const Pending& b) {
    return a.sec != b.sec ? a.sec < b.sec : a.nsec < b.nsec;
  });
}

bool BagFile::read_record() {
  if (done_) return false;
  const std::uint64_t at = offset_;
  if (at == size_) {
    done_ = true;
    return false;
  }
  auto left = [&](std::uint64_t from) { return size_ - from; };
  if (left(at) < 4) {
    stop(at, fmt::format("the file ends {} bytes into a record's header length", left(at)));
    return false;
  }
  std::uint8_t len_bytes[4];
  in_.seekg(static_cast<std::streamoff>(at));
  in_.read(reinterpret_cast<char*>(len_bytes), 4);
  const std::uint32_t hlen = le32(len_bytes);
  if (hlen > kMaxRecordHeader) {
    stop(at, fmt::format("record header length {} is not plausible (at most {})", hlen,
                         kMaxRecordHeader));
    return false;
  }
  if (hlen > left(at + 4) || left(at + 4) - hlen < 4) {
    stop(at, fmt::format("the file ends inside a record header ({} bytes declared, {} left)",
                         hlen, left(at + 4)));
    return false;
  }
  std::vector<std::uint8_t> header(hlen);
  in_.read(reinterpret_cast<char*>(header.data()), hlen);
  in_.read(reinterpret_cast<char*>(len_bytes), 4);
  if (!in_) {
    stop(at, "read error");
    return false;
  }
  const std::uint32_t dlen = le32(len_bytes);
  const std::uint64_t data_at = at + 8 + hlen;
  const std::uint64_t available = std::min<std::uint64_t>(dlen, left(data_at));
  const bool truncated = available < dlen;
  const Fields f = parse_fields(header);
  if (!f.error.empty() || !f.op()) {
    stop(at, "malformed record header: " + (f.error.empty() ? std::string("no op field") : f.error));
    return false;
  }
  const std::uint8_t op = *f.op();
  auto read_data = [&](std::vector<std::uint8_t>& buf) {
    check_memory_budget(available, "a ROS bag record");
    buf.resize(available);
    in_.read(reinterpret_cast<char*>(buf.data()), static_cast<std::streamsize>(available));
  };
  switch (op) {
    case kOpBagHeader:
      stats_.indexed = f.u64("index_pos").value_or(0) != 0;
      break;
    case kOpChunk: {
      const std::string compression = f.str("compression").value_or("");
      const auto size = f.u32("size");
      if (!size || (compression != "none" && compression != "bz2" && compression != "lz4")) {
        stop(at, size ? fmt::format("chunk compression \"{}\" is not none, bz2 or lz4",
                                    printable(compression))
                      : "chunk record without its size field");
        return false;
      }
      ++stats_.chunks_by_compression[compression];
      check_memory_budget(*size, "a ROS bag chunk");
      std::vector<std::uint8_t> raw;
      read_data(raw);
      std::string error;
      std::size_t produced = 0;
      if (compression == "none") {
        produced = std::min<std::size_t>(raw.size(), *size);
        chunk_.assign(raw.begin(), raw.begin() + static_cast<std::ptrdiff_t>(produced));
        if (!truncated && raw.size() != *size) {
          error = fmt::format("holds {} bytes, its header says {}", raw.size(), *size);
        }
      } else if (compression == "bz2") {
        produced = bunzip2(raw, chunk_, *size, error);
      } else {
        produced = unlz4(raw, chunk_, *size, error);
      }
      parse_chunk_records(produced, at);
      if (truncated) {
        stop(at, fmt::format("the file ends {} bytes into a {} chunk of {} bytes (messages in "
                             "its first {} decompressed bytes were read)",
                             available, compression, dlen, produced));
      } else if (!error.empty()) {
        stop(at, fmt::format("{} chunk: {} (messages in its first {} decompressed bytes were "
                             "read)", compression, error, produced));
      }
      offset_ = truncated ? size_ : data_at + dlen;
      return true;
    }
    case kOpConnection: {
      const auto id = f.u32("conn");
      if (!truncated && id) {
        std::vector<std::uint8_t> data;
        read_data(data);
        add_connection(*id, f.str("topic").value_or(""), data);
      }
      break;
    }
    case kOpMessage: {
      // A message outside any chunk (not written by rosbag, but valid).
      const auto conn = f.u32("conn");
      const auto time = f.u64("time");
      if (conn && time && !truncated) {
        read_data(chunk_);
        pending_.assign(1, {*conn, static_cast<std::uint32_t>(*time & 0xffffffffu),
                            static_cast<std::uint32_t>(*time >> 32), 0, chunk_.size()});
        next_pending_ = 0;
      }
      break;
    }
    case kOpIndex:
    case kOpChunkInfo:
      break;
    default:
      ++stats_.unknown_records;
      break;
  }
  if (truncated) {
    stop(at, fmt::format("the file ends {} bytes into a record of {} bytes (op 0x{:02x})",
                         available, dlen, op));
    offset_ = size_;
    return true;
  }
  offset_ = data_at + dlen;
  return true;
}

std::optional<BagMessage> BagFile::next() {
  while (true) {
    while (next_pending_ < pending_.size()) {
      const Pending& p = pending_[next_pending_++];
      auto it = connections_.find(p.conn);
      if (it == connections_.end()) {
        ++stats_.orphan_messages;
        continue;
      }
      ++stats_.messages;
      return BagMessage{&it->second, p.sec, p.nsec,
                        std::span<const std::uint8_t>(chunk_.data() + p.begin, p.size)};
    }
    pending_.clear();
    next_pending_ = 0;
    if (!read_record()) return std::nullopt;
  }
}

}  // namespace rove::bag_detail
