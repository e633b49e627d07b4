// libFuzzer target for rove::RoveRawlogReader. Any bytes must either read or
// be rejected with a rove::Error. Whatever is read must write back to a
// rove rawlog that reads again, and writing that second reading must give
// the same bytes (write ∘ read is the identity on written files).

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <vector>

#include "rove/core/error.h"
#include "rove/io/rove_rawlog.h"
#include "rove/serialization/memory_stream.h"

namespace {

rove::RoveRawlogReaderOptions reader_options(bool skip) {
  rove::RoveRawlogReaderOptions o;
  o.limits.max_length = std::uint64_t{1} << 20;
  o.limits.max_nesting = 16;
  o.max_entry_bytes = std::uint64_t{1} << 22;
  o.skip_unknown_classes = skip;
  return o;
}

struct Read {
  std::vector<rove::RawlogEntry> entries;
  rove::RawlogLayout layout = rove::RawlogLayout::Empty;
  rove::RawlogMetadata metadata;
};

Read read_all(std::vector<std::byte> bytes, bool skip) {
  rove::RoveRawlogReader r(std::make_unique<rove::MemoryInStream>(std::move(bytes), "fuzz"),
                           reader_options(skip));
  Read out;
  out.layout = r.layout();
  out.metadata = r.metadata();
  while (auto e = r.next()) out.entries.push_back(std::move(*e));
  return out;
}

std::vector<std::byte> write_all(const Read& in) {
  auto stream = std::make_unique<rove::MemoryOutStream>("fuzz-out");
  auto* raw = stream.get();
  rove::RoveRawlogWriterOptions o;
  o.layout = in.layout;
  o.metadata = in.metadata;
  rove::RoveRawlogWriter w(std::move(stream), o);
  for (const auto& e : in.entries) w.write(e);
  w.close();
  return raw->data();
}

[[noreturn]] void die(const char* what) {
  std::fprintf(stderr, "rove_rawlog_fuzz: %s\n", what);
  std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::vector<std::byte> bytes(size);
  if (size > 0) std::memcpy(bytes.data(), data, size);
  for (bool skip : {false, true}) {
    Read first;
    try {
      first = read_all(bytes, skip);
    } catch (const rove::Error&) {
      continue;  // rejected: fine
    }
    std::vector<std::byte> written;
    try {
      written = write_all(first);
    } catch (const rove::Error&) {
      // An object the reader accepted but the writer refuses (a failed
      // precondition check) means the reader let inconsistent data through.
      die("an entry that was read cannot be written back");
    }
    Read second;
    try {
      second = read_all(written, false);
    } catch (const rove::Error& e) {
      std::fprintf(stderr, "%s\n", e.what());
      die("a file written from read entries does not read back");
    }
    if (second.entries.size() != first.entries.size()) die("entry count changed");
    if (write_all(second) != written) die("write(read(write(x))) != write(x)");
  }
  return 0;
}
