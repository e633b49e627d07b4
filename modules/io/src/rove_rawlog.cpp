#include "rove/io/rove_rawlog.h"

#include <fmt/format.h>

#include <algorithm>
#include <cstring>
#include <utility>

#include "rove/core/check.h"
#include "rove/core/error.h"
#include "rove/obs/obs_registry.h"
#include "rove/serialization/class_registry.h"
#include "rove/serialization/file_stream.h"
#include "rove/serialization/gzip_stream.h"
#include "rove/serialization/input_file.h"
#include "rove/serialization/memory_stream.h"
#include "rove/serialization/object_io.h"

namespace rove {
namespace {

constexpr std::uint32_t kMaxClassName = 255;

std::uint8_t layout_byte(RawlogLayout layout) { return static_cast<std::uint8_t>(layout); }

bool layout_allows(RawlogLayout layout, bool is_observation) {
  switch (layout) {
    case RawlogLayout::ActionsSensoryFrames: return !is_observation;
    case RawlogLayout::Observations: return is_observation;
    case RawlogLayout::Mixed: return true;
    case RawlogLayout::Empty: return false;
  }
  return false;
}

const char* layout_name(RawlogLayout layout) {
  switch (layout) {
    case RawlogLayout::ActionsSensoryFrames: return "#1 (action collections + sensory frames)";
    case RawlogLayout::Observations: return "#2 (observations)";
    case RawlogLayout::Mixed: return "mixed";
    case RawlogLayout::Empty: return "empty";
  }
  return "?";
}

// The bytes of one entry record, read straight from the file's stream:
// offsets stay those of the file, remaining() is bounded by the record's
// declared length (so hostile lengths inside it are rejected early), and a
// prefix can be looked at before the record is parsed (the class name).
class EntryStream final : public InStream {
 public:
  EntryStream(InStream& under, std::uint64_t length)
      : under_(under), start_(under.offset()), length_(length) {}

  // Makes the first `n` bytes available in `peeked()` (fewer at the end of
  // the record or of the file); they are still returned by read_some.
  std::span<const std::byte> peek(std::size_t n) {
    n = static_cast<std::size_t>(std::min<std::uint64_t>(n, length_));
    while (buffer_.size() < n) {
      std::byte chunk[256];
      const std::size_t want = std::min(sizeof(chunk), n - buffer_.size());
      const std::size_t got = under_.read_some(std::span<std::byte>(chunk, want));
      if (got == 0) break;
      buffer_.insert(buffer_.end(), chunk, chunk + got);
      fetched_ += got;
    }
    return std::span<const std::byte>(buffer_.data(), buffer_.size());
  }

  std::size_t read_some(std::span<std::byte> out) override {
    std::size_t n = 0;
    if (served_ < buffer_.size()) {
      n = std::min(out.size(), buffer_.size() - static_cast<std::size_t>(served_));
      std::memcpy(out.data(), buffer_.data() + served_, n);
      served_ += n;
      out = out.subspan(n);
    }
    if (!out.empty() && fetched_ < length_) {
      const std::size_t want =
          static_cast<std::size_t>(std::min<std::uint64_t>(out.size(), length_ - fetched_));
      const std::size_t got = under_.read_some(out.first(want));
      fetched_ += got;
      served_ += got;
      n += got;
    }
    return n;
  }
  std::uint64_t offset() const override { return start_ + served_; }
  std::optional<std::uint64_t> remaining() const override {
    std::uint64_t left = length_ - served_;
    if (auto r = under_.remaining()) {
      left = std::min<std::uint64_t>(left, *r + (fetched_ - served_));
    }
    return left;
  }
  const std::string& source_name() const override { return under_.source_name(); }

  // Reads and drops what is left of the record; returns the bytes dropped.
  std::uint64_t discard_rest() {
    std::byte chunk[4096];
    std::uint64_t dropped = 0;
    for (;;) {
      const std::size_t got = read_some(chunk);
      if (got == 0) break;
      dropped += got;
    }
    return dropped;
  }
  std::uint64_t consumed() const { return served_; }
  std::uint64_t length() const { return length_; }

 private:
  InStream& under_;
  std::uint64_t start_;
  std::uint64_t length_;
  std::vector<std::byte> buffer_;
  std::uint64_t fetched_ = 0;  // bytes taken from under_
  std::uint64_t served_ = 0;   // bytes handed out by read_some
};

template <typename T>
std::shared_ptr<const T> take_as(std::unique_ptr<Serializable>& obj) {
  if (auto* p = dynamic_cast<T*>(obj.get())) {
    obj.release();
    return std::shared_ptr<const T>(p);
  }
  return nullptr;
}

}  // namespace

// ----------------------------------------------------------------- writer

RoveRawlogWriter::RoveRawlogWriter(const std::string& path, RoveRawlogWriterOptions options)
    : options_(std::move(options)) {
  ROVE_CHECK_MSG(options_.gzip_level >= 1 && options_.gzip_level <= 9,
                 "gzip_level must be in 1..9, got {}", options_.gzip_level);
  ROVE_CHECK_MSG(options_.layout != RawlogLayout::Empty,
                 "a rove rawlog is written with layout #1, #2 or mixed");
  if (options_.gzip) {
    stream_ = std::make_unique<GzipFileOutStream>(path, options_.gzip_level);
  } else {
    stream_ = std::make_unique<FileOutStream>(path);
  }
  archive_ = std::make_unique<OutArchive>(*stream_);
  write_header();
}

RoveRawlogWriter::RoveRawlogWriter(std::unique_ptr<OutStream> stream,
                                   RoveRawlogWriterOptions options)
    : options_(std::move(options)), stream_(std::move(stream)) {
  ROVE_CHECK_MSG(stream_ != nullptr, "RoveRawlogWriter needs a stream");
  ROVE_CHECK_MSG(options_.layout != RawlogLayout::Empty,
                 "a rove rawlog is written with layout #1, #2 or mixed");
  archive_ = std::make_unique<OutArchive>(*stream_);
  write_header();
}

RoveRawlogWriter::~RoveRawlogWriter() = default;

void RoveRawlogWriter::write_header() {
  archive_->write_bytes(std::as_bytes(std::span<const char>(kRoveRawlogMagic)));
  archive_->write_scalar(kRoveRawlogFormatVersion);
  archive_->write_scalar(layout_byte(options_.layout));
  archive_->write_length(options_.metadata.size(), "metadata count");
  for (const auto& [key, value] : options_.metadata) {
    save(*archive_, key);
    save(*archive_, value);
  }
}

void RoveRawlogWriter::write_record(const Serializable& obj, bool is_observation) {
  ROVE_CHECK_MSG(!closed_, "write after close on a rove rawlog ({})", stream_->source_name());
  ROVE_CHECK_MSG(layout_allows(options_.layout, is_observation),
                 "a {} cannot go into a rove rawlog of layout {}", obj.class_name(),
                 layout_name(options_.layout));
  MemoryOutStream buffer;
  OutArchive record(buffer);
  write_object(record, obj);
  archive_->write_scalar(static_cast<std::uint64_t>(buffer.data().size()));
  archive_->write_bytes(buffer.data());
  ++entries_;
}

void RoveRawlogWriter::write(const ActionCollection& actions) { write_record(actions, false); }
void RoveRawlogWriter::write(const SensoryFrame& frame) { write_record(frame, false); }
void RoveRawlogWriter::write(const Observation& observation) { write_record(observation, true); }

void RoveRawlogWriter::write(const RawlogEntry& entry) {
  std::visit([this](const auto& e) { write(*e); }, entry);
}

void RoveRawlogWriter::close() {
  if (closed_) return;
  closed_ = true;
  archive_->write_scalar(std::uint64_t{0});
  archive_->write_scalar(entries_);
  if (auto* gz = dynamic_cast<GzipFileOutStream*>(stream_.get())) {
    gz->close();
  } else if (auto* file = dynamic_cast<FileOutStream*>(stream_.get())) {
    file->close();
  } else {
    stream_->flush();
  }
}

std::uint64_t RoveRawlogWriter::bytes_written() const { return stream_->offset(); }

// ----------------------------------------------------------------- reader

RoveRawlogReader::RoveRawlogReader(const std::string& path, RoveRawlogReaderOptions options)
    : options_(options), path_(path), stream_(open_input_file(path)) {
  archive_ = std::make_unique<InArchive>(*stream_, options_.limits);
  read_header();
}

RoveRawlogReader::RoveRawlogReader(std::unique_ptr<InStream> stream,
                                   RoveRawlogReaderOptions options)
    : options_(options), stream_(std::move(stream)) {
  ROVE_CHECK_MSG(stream_ != nullptr, "RoveRawlogReader needs a stream");
  path_ = stream_->source_name();
  archive_ = std::make_unique<InArchive>(*stream_, options_.limits);
  read_header();
}

RoveRawlogReader::~RoveRawlogReader() = default;

std::uint64_t RoveRawlogReader::offset() const { return archive_->offset(); }

void RoveRawlogReader::read_header() {
  register_obs_classes();
  std::array<char, 8> magic{};
  const std::uint64_t start = archive_->offset();
  const std::size_t got = stream_->read_some(std::as_writable_bytes(std::span<char>(magic)));
  if (got != magic.size() || magic != kRoveRawlogMagic) {
    archive_->fail_at(start, "magic",
                      "not a rove rawlog: the file does not start with \"ROVERAWL\"");
  }
  const std::uint64_t version_at = archive_->offset();
  format_version_ = archive_->read_scalar<std::uint16_t>("format version");
  if (format_version_ == 0 || format_version_ > kRoveRawlogFormatVersion) {
    archive_->fail_at(version_at, "format version",
                      fmt::format("rove rawlog format version {} is not one this build reads "
                                  "(1..{})",
                                  format_version_, kRoveRawlogFormatVersion));
  }
  const std::uint64_t layout_at = archive_->offset();
  const auto layout = archive_->read_scalar<std::uint8_t>("layout");
  if (layout < 1 || layout > 3) {
    archive_->fail_at(layout_at, "layout",
                      fmt::format("layout must be 1, 2 or 3 (mixed), found {}", layout));
  }
  layout_ = static_cast<RawlogLayout>(layout);
  // A key and a value take at least 4 bytes each.
  const std::uint32_t n = archive_->read_length("metadata count", 8);
  for (std::uint32_t i = 0; i < n; ++i) {
    const std::uint64_t at = archive_->offset();
    std::string key, value;
    load(*archive_, key);
    load(*archive_, value);
    if (!metadata_.emplace(std::move(key), std::move(value)).second) {
      archive_->fail_at(at, "metadata", "duplicate metadata key");
    }
  }
}

std::optional<RawlogEntry> RoveRawlogReader::next() {
  while (!done_) {
    const std::uint64_t at = archive_->offset();
    const auto length = archive_->read_scalar<std::uint64_t>("entry length");
    if (length == 0) {
      const std::uint64_t count_at = archive_->offset();
      const auto count = archive_->read_scalar<std::uint64_t>("entry count");
      if (count != entries_read_ + skipped_) {
        archive_->fail_at(count_at, "entry count",
                          fmt::format("the end record counts {} entries, the file holds {}",
                                      count, entries_read_ + skipped_));
      }
      if (!archive_->at_end()) {
        archive_->fail_at(archive_->offset(), "end record", "bytes follow the end record");
      }
      done_ = true;
      return std::nullopt;
    }
    if (length > options_.max_entry_bytes) {
      archive_->fail_at(at, "entry length",
                        fmt::format("entry of {} bytes exceeds the limit of {} bytes", length,
                                    options_.max_entry_bytes));
    }
    if (auto left = stream_->remaining(); left && length > *left) {
      archive_->fail_at(at, "entry length",
                        fmt::format("entry of {} bytes, but only {} bytes are left", length,
                                    *left));
    }
    const std::uint64_t record_at = archive_->offset();
    EntryStream entry(*stream_, length);

    // The class name, looked at before parsing so unknown classes can be
    // passed over whole.
    const auto head = entry.peek(4);
    if (head.size() < 4) archive_->fail_at(record_at, "class name length", "truncated entry");
    const auto name_length = InArchive::decode<std::uint32_t>(head.data());
    if (name_length == 0 || name_length > kMaxClassName) {
      archive_->fail_at(record_at, "class name length",
                        fmt::format("class name length {} is outside 1..{}", name_length,
                                    kMaxClassName));
    }
    const auto named = entry.peek(4 + name_length);
    if (named.size() < 4 + name_length) {
      archive_->fail_at(record_at, "class name", "truncated entry");
    }
    const std::string class_name(reinterpret_cast<const char*>(named.data()) + 4, name_length);
    if (!ClassRegistry::global().contains(class_name)) {
      if (!options_.skip_unknown_classes) {
        archive_->fail_at(record_at, class_name,
                          fmt::format("unknown class '{}' in entry {}", class_name,
                                      entries_read_ + skipped_));
      }
      entry.discard_rest();
      if (entry.consumed() != length) {
        archive_->fail_at(entry.offset(), class_name, "truncated entry");
      }
      ++skipped_;
      continue;
    }

    InArchive record(entry, options_.limits);
    std::unique_ptr<Serializable> obj = read_object(record);
    if (entry.consumed() != length) {
      archive_->fail_at(entry.offset(), class_name,
                        fmt::format("entry declared {} bytes but its object ends after {}",
                                    length, entry.consumed()));
    }

    std::optional<RawlogEntry> out;
    bool is_observation = false;
    if (auto ac = take_as<ActionCollection>(obj)) {
      out = RawlogEntry(std::move(ac));
    } else if (auto sf = take_as<SensoryFrame>(obj)) {
      out = RawlogEntry(std::move(sf));
    } else if (auto o = take_as<Observation>(obj)) {
      out = RawlogEntry(std::move(o));
      is_observation = true;
    } else {
      archive_->fail_at(record_at, class_name,
                        "a rawlog entry must be an ActionCollection, a SensoryFrame or an "
                        "observation");
    }
    if (!layout_allows(layout_, is_observation)) {
      archive_->fail_at(record_at, class_name,
                        fmt::format("a {} does not belong in a rawlog of layout {}", class_name,
                                    layout_name(layout_)));
    }
    ++entries_read_;
    return out;
  }
  return std::nullopt;
}

RoveRawlog load_rove_rawlog(const std::string& path, RoveRawlogReaderOptions options) {
  RoveRawlogReader reader(path, options);
  RoveRawlog out;
  out.layout = reader.layout();
  out.metadata = reader.metadata();
  while (auto e = reader.next()) out.entries.push_back(std::move(*e));
  return out;
}

RawlogLayout layout_of(const std::vector<RawlogEntry>& entries) {
  bool frames = false;
  bool observations = false;
  for (const auto& e : entries) {
    if (std::holds_alternative<std::shared_ptr<const Observation>>(e)) {
      observations = true;
    } else {
      frames = true;
    }
  }
  if (frames && observations) return RawlogLayout::Mixed;
  if (frames) return RawlogLayout::ActionsSensoryFrames;
  if (observations) return RawlogLayout::Observations;
  return RawlogLayout::Empty;
}

void save_rove_rawlog(const std::string& path, const std::vector<RawlogEntry>& entries,
                      RoveRawlogWriterOptions options) {
  const RawlogLayout layout = layout_of(entries);
  if (layout != RawlogLayout::Empty) options.layout = layout;
  RoveRawlogWriter writer(path, std::move(options));
  for (const auto& e : entries) writer.write(e);
  writer.close();
}

}  // namespace rove
