#pragma once
/// \file
/// Dispatch of MRPT object payloads to readers by class name. MRPT records
/// carry no payload length, so an object of an unknown class cannot be
/// skipped: every class a file contains needs a reader here.

#include <fmt/format.h>

#include <concepts>
#include <functional>
#include <string>
#include <string_view>
#include <unordered_map>
#include <utility>

#include "rove/core/check.h"
#include "rove/serialization/archive.h"
#include "rove/serialization/mrpt_format.h"

namespace rove {

/// Class name → function reading that class's payload (for the version in the
/// header) into a `Result`, e.g. a variant or a pointer to a rove type.
/// Readers of container classes call read_object recursively for the objects
/// inside them.
///
/// Thread-safety: const members may be called concurrently; add() must not
/// run concurrently with anything else on the same object.
template <std::default_initializable Result>
class MrptClassReaders {
 public:
  /// Reads the payload of the object whose header was just read (the end
  /// marker is left to read_object). Unknown versions should be reported
  /// with throw_unknown_mrpt_version.
  using Reader = std::function<Result(InArchive&, const MrptObjectHeader&)>;

  /// Registers `reader` for `class_name`; throws rove::InvalidArgument if the
  /// name is already registered or the reader is empty.
  void add(std::string class_name, Reader reader) {
    ROVE_CHECK_MSG(static_cast<bool>(reader), "empty reader for MRPT class '{}'", class_name);
    const bool inserted = readers_.emplace(class_name, std::move(reader)).second;
    ROVE_CHECK_MSG(inserted, "MRPT class '{}' already has a reader", class_name);
  }

  /// Whether `class_name` has a reader.
  bool contains(std::string_view class_name) const {
    return readers_.find(std::string(class_name)) != readers_.end();
  }

  /// Reads one whole object: header, payload through the registered reader,
  /// end marker. MRPT's null object gives a value-initialized Result. Throws
  /// rove::ParseError naming the class and the record's offset when the class
  /// has no reader, and on malformed data.
  Result read_object(InArchive& ar) const {
    const InArchive::NestingGuard nesting(ar, "MRPT object");
    const MrptObjectHeader header = read_mrpt_object_header(ar);
    if (header.is_null) {
      expect_mrpt_end_marker(ar, header);
      return Result{};
    }
    const auto it = readers_.find(header.class_name);
    if (it == readers_.end()) {
      ar.fail_at(header.offset, header.class_name,
                 fmt::format("no reader for MRPT class '{}' (version {})", header.class_name,
                             header.version));
    }
    Result result = it->second(ar, header);
    expect_mrpt_end_marker(ar, header);
    return result;
  }

 private:
  std::unordered_map<std::string, Reader> readers_;
};

}  // namespace rove
