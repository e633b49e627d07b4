#include "rove/io/any_rawlog.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <span>
#include <cstring>
#include <utility>

#include "rove/core/error.h"
#include "rove/core/files.h"
#include "rove/io/carmen_log.h"
#include "rove/serialization/input_file.h"

namespace rove {
namespace {

// How much of a text file is searched for a CARMEN message line (a log's
// comments and PARAM lines come first; they take a few KiB).
constexpr std::size_t kCarmenSniffBytes = std::size_t{256} << 10;

// An MRPT object starts with 0x80 | name length (or, before MRPT 0.5.5, a
// u32 length below 128), then the class name: printable ASCII, 1..120 bytes.
bool starts_with_mrpt_object(std::span<const std::byte> head) {
  if (head.empty()) return false;
  const auto first = std::to_integer<unsigned char>(head[0]);
  std::size_t len = first & 0x7Fu;
  std::size_t name_at = 1;
  if ((first & 0x80u) == 0) {
    if (head.size() < 4) return false;
    for (std::size_t i = 1; i < 4; ++i) {
      if (head[i] != std::byte{0}) return false;
    }
    name_at = 4;
  }
  if (len == 0 || len > 120) return false;
  const std::size_t end = std::min(head.size(), name_at + len);
  if (end <= name_at) return false;
  for (std::size_t i = name_at; i < end; ++i) {
    const auto c = std::to_integer<unsigned char>(head[i]);
    if (c < 0x21 || c > 0x7e) return false;
  }
  return true;
}

bool is_text_byte(unsigned char c) { return c == '\t' || c == '\n' || c == '\r' || (c >= 0x20 && c < 0x7f); }

RawlogSourceOpener& bag_opener() {
  static RawlogSourceOpener opener;
  return opener;
}

}  // namespace

void register_rawlog_source(RawlogFormat format, RawlogSourceOpener opener) {
  if (format != RawlogFormat::RosBag) {
    throw InvalidArgument(fmt::format("register_rawlog_source: {} logs have a built-in reader",
                                      to_string(format)));
  }
  bag_opener() = std::move(opener);
}

bool rawlog_format_available(RawlogFormat format) {
  return format != RawlogFormat::RosBag || static_cast<bool>(bag_opener());
}

std::string_view to_string(RawlogFormat format) noexcept {
  switch (format) {
    case RawlogFormat::Rove: return "rove";
    case RawlogFormat::Mrpt: return "MRPT";
    case RawlogFormat::Carmen: return "CARMEN";
    case RawlogFormat::RosBag: return "ROS bag";
  }
  return "unknown";
}

RawlogFormat detect_rawlog_format(const std::string& path) {
  check_regular_input(path, "rawlog");
  std::unique_ptr<InStream> in = open_input_file(path);
  std::array<std::byte, 128> head{};
  std::size_t n = 0;
  while (n < head.size()) {
    const std::size_t got = in->read_some(std::span<std::byte>(head).subspan(n));
    if (got == 0) break;
    n += got;
  }
  if (n == 0) {
    throw ParseError({path, std::nullopt, 0, "format"},
                     "empty file: not a rove rawlog, MRPT rawlog or CARMEN log");
  }
  if (n >= kRoveRawlogMagic.size() &&
      std::memcmp(head.data(), kRoveRawlogMagic.data(), kRoveRawlogMagic.size()) == 0) {
    return RawlogFormat::Rove;
  }
  if (n >= kRosBagMagic.size() &&
      std::memcmp(head.data(), kRosBagMagic.data(), kRosBagMagic.size()) == 0) {
    return RawlogFormat::RosBag;
  }
  if (n >= 9 && std::memcmp(head.data(), "#ROSBAG V", 9) == 0) {
    throw ParseError({path, std::nullopt, 0, "format"},
                     "a ROS bag of a format version other than 2.0 (rove reads ROS 1 bags, "
                     "format 2.0)");
  }
  const bool bzip2 = n >= 3 && std::memcmp(head.data(), "BZh", 3) == 0;
  bool text = true;
  for (std::size_t i = 0; i < std::min<std::size_t>(n, 8); ++i) {
    text = text && is_text_byte(std::to_integer<unsigned char>(head[i]));
  }
  if (!bzip2 && !text) {
    if (!starts_with_mrpt_object(std::span<const std::byte>(head.data(), n))) {
      throw ParseError({path, std::nullopt, 0, "format"},
                       "not a rove rawlog, MRPT rawlog or CARMEN log: binary data that does not "
                       "start with an MRPT object header (class name length and name)");
    }
    return RawlogFormat::Mrpt;
  }
  // Text (or bzip2): a CARMEN log only if it holds CARMEN message lines.
  if (!bzip2 && is_gzip_file(path)) {
    throw ParseError({path, std::nullopt, 0, "format"},
                     "gzip-compressed text: rove reads CARMEN logs plain or bzip2-compressed "
                     "(decompress it first); it is not a rove or MRPT rawlog");
  }
  if (!looks_like_carmen_log(path, kCarmenSniffBytes)) {
    throw ParseError({path, std::nullopt, 0, "format"},
                     fmt::format("not a rove rawlog, MRPT rawlog or CARMEN log: {} with no CARMEN "
                                 "message line (FLASER, RLASER, ROBOTLASER1, ODOM, TRUEPOS, "
                                 "PARAM, ...) in its first {} KiB",
                                 bzip2 ? "bzip2-compressed text" : "text",
                                 kCarmenSniffBytes / 1024));
  }
  return RawlogFormat::Carmen;
}

AnyRawlogReader::AnyRawlogReader(const std::string& path, AnyRawlogOptions options)
    : path_(path), format_(detect_rawlog_format(path)) {
  switch (format_) {
    case RawlogFormat::Rove:
      rove_ = std::make_unique<RoveRawlogReader>(path, options.rove);
      break;
    case RawlogFormat::Mrpt:
      mrpt_ = std::make_unique<RawlogReader>(path, options.mrpt);
      break;
    case RawlogFormat::Carmen:
      carmen_ = std::make_unique<CarmenRawlogSource>(
          CarmenRawlogSource::open(path, std::move(options.carmen)));
      break;
    case RawlogFormat::RosBag:
      if (!bag_opener()) {
        throw ParseError({path, std::nullopt, 0, "format"},
                         "a ROS bag, but this build of rove has no ROS bag reader (build it with "
                         "the rove::ros adapter: Debian's librosbag-storage-dev and message "
                         "packages, ROVE_BUILD_ROS=ON)");
      }
      source_ = bag_opener()(path, options);
      break;
  }
}

AnyRawlogReader::~AnyRawlogReader() = default;

std::optional<RawlogEntry> AnyRawlogReader::next() {
  std::optional<RawlogEntry> e;
  if (rove_) {
    e = rove_->next();
  } else if (mrpt_) {
    e = mrpt_->next();
  } else if (source_) {
    e = source_->next();
  } else {
    e = carmen_->next();
    if (!e) {
      const CarmenLogStats& s = carmen_->stats().log;
      if (s.records() == 0) {
        throw ParseError(
            {path_, s.lines, std::nullopt, "records"},
            fmt::format("no CARMEN record (FLASER, RLASER, ROBOTLASER1, ODOM, TRUEPOS) in its {} "
                        "lines ({} PARAM, {} SYNC, {} of other messages, {} comments, {} "
                        "malformed): not a robot log",
                        s.lines, s.param, s.sync, s.other, s.comments, s.malformed));
      }
      if (entries_ == 0) {
        // ODOM or TRUEPOS lines alone give no entry in layout #1 (odometry
        // only goes between two scans) and TRUEPOS none in either layout.
        throw ParseError(
            {path_, s.lines, std::nullopt, "records"},
            fmt::format("no rawlog entry from its {} CARMEN records ({} ODOM, {} TRUEPOS, no "
                        "laser scan{}): not a robot log in this layout",
                        s.records(), s.odom, s.truepos,
                        carmen_->layout() == RawlogLayout::ActionsSensoryFrames
                            ? "; odometry alone gives entries only in layout #2"
                            : ""));
      }
    }
  }
  if (e) ++entries_;
  return e;
}

std::uint64_t AnyRawlogReader::position() const {
  if (rove_) return rove_->offset();
  if (mrpt_) return mrpt_->offset();
  if (source_) return source_->position();
  return carmen_->lines_read();
}

std::optional<RawlogLayout> AnyRawlogReader::declared_layout() const {
  if (rove_) return rove_->layout();
  if (carmen_) return carmen_->layout();
  if (source_) return source_->layout();
  return std::nullopt;
}

std::vector<std::string> AnyRawlogReader::skipped() const {
  if (source_) return source_->skipped();
  if (rove_ && rove_->skipped_entries() > 0) {
    return {fmt::format("{} entries of unknown classes", rove_->skipped_entries())};
  }
  return {};
}

AnyRawlog load_any_rawlog(const std::string& path, AnyRawlogOptions options) {
  AnyRawlogReader reader(path, std::move(options));
  AnyRawlog out;
  out.format = reader.format();
  while (auto e = reader.next()) out.entries.push_back(std::move(*e));
  out.layout = layout_of(out.entries);
  return out;
}

}  // namespace rove
