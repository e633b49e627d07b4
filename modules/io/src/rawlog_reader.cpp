#include "rove/io/rawlog_reader.h"

#include <fmt/format.h>

#include <utility>

#include "rove/core/check.h"
#include "rove/io/mrpt_objects.h"
#include "rove/serialization/input_file.h"

namespace rove {

RawlogReader::RawlogReader(const std::string& path, RawlogReaderOptions options)
    : path_(path), stream_(open_input_file(path)) {
  archive_ = std::make_unique<InArchive>(*stream_, options.limits);
}

RawlogReader::RawlogReader(std::unique_ptr<InStream> stream, RawlogReaderOptions options)
    : stream_(std::move(stream)) {
  ROVE_CHECK_MSG(stream_ != nullptr, "RawlogReader needs a stream");
  path_ = stream_->source_name();
  archive_ = std::make_unique<InArchive>(*stream_, options.limits);
}

RawlogReader::~RawlogReader() = default;

std::uint64_t RawlogReader::offset() const { return archive_->offset(); }

std::optional<RawlogEntry> RawlogReader::next() {
  while (!archive_->at_end()) {
    const std::uint64_t at = archive_->offset();
    MrptObject o = read_mrpt_object(*archive_);
    if (std::holds_alternative<std::monostate>(o)) continue;
    ++entries_read_;
    if (auto* sf = std::get_if<std::shared_ptr<SensoryFrame>>(&o)) {
      return RawlogEntry(std::shared_ptr<const SensoryFrame>(std::move(*sf)));
    }
    if (auto* ac = std::get_if<std::shared_ptr<ActionCollection>>(&o)) {
      return RawlogEntry(std::shared_ptr<const ActionCollection>(std::move(*ac)));
    }
    if (auto* obs = std::get_if<std::shared_ptr<Observation>>(&o)) {
      return RawlogEntry(std::shared_ptr<const Observation>(std::move(*obs)));
    }
    archive_->fail_at(at, "rawlog entry",
                      "a rawlog entry must be a CActionCollection, a CSensoryFrame or an "
                      "observation");
  }
  return std::nullopt;
}

Rawlog load_rawlog(const std::string& path, RawlogReaderOptions options) {
  RawlogReader reader(path, options);
  Rawlog out;
  bool has_frames = false;
  bool has_observations = false;
  while (auto e = reader.next()) {
    if (std::holds_alternative<std::shared_ptr<const Observation>>(*e)) {
      has_observations = true;
    } else {
      has_frames = true;
    }
    out.entries.push_back(std::move(*e));
  }
  if (has_frames && has_observations) {
    out.layout = RawlogLayout::Mixed;
  } else if (has_frames) {
    out.layout = RawlogLayout::ActionsSensoryFrames;
  } else if (has_observations) {
    out.layout = RawlogLayout::Observations;
  }
  return out;
}

}  // namespace rove
