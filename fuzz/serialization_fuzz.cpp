// libFuzzer target for rove::serialization. The first input byte picks the
// reader; the rest is the data:
//   0: a stream of rove objects (read_object) of a few registered test types;
//      every object read must write back and read again to the same bytes;
//   1: MRPT object framing (read_mrpt_object_header and MrptClassReaders for
//      CMatrixD, CPose3D and a generic container class);
//   2: a nested STL / Eigen value loaded directly.
// Malformed input must raise rove::ParseError; anything else aborts.

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <variant>
#include <vector>

#include "rove/core/error.h"
#include "rove/serialization/eigen.h"
#include "rove/serialization/memory_stream.h"
#include "rove/serialization/mrpt_class_readers.h"
#include "rove/serialization/mrpt_format.h"
#include "rove/serialization/object_io.h"
#include "rove/serialization/stl.h"

namespace {

[[noreturn]] void die(const char* what) {
  std::fprintf(stderr, "serialization_fuzz: %s\n", what);
  std::abort();
}

class Scan final : public rove::Serializable {
 public:
  std::vector<float> ranges;
  std::map<std::string, std::int32_t> labels;
  std::optional<Eigen::Matrix3d> pose;
  std::string_view class_name() const override { return "fuzz.Scan"; }
  std::uint8_t version() const override { return 1; }
  void save_payload(rove::OutArchive& ar) const override { ar << ranges << labels << pose; }
  void load_payload(rove::InArchive& ar, std::uint8_t version) override {
    ar >> ranges >> labels;
    if (version >= 1) {
      ar >> pose;
    } else {
      pose.reset();
    }
  }
};

class Frame final : public rove::Serializable {
 public:
  std::vector<std::unique_ptr<rove::Serializable>> items;
  Eigen::MatrixXf grid;
  std::string_view class_name() const override { return "fuzz.Frame"; }
  std::uint8_t version() const override { return 0; }
  void save_payload(rove::OutArchive& ar) const override {
    ar << grid;
    ar.write_length(items.size(), "items");
    for (const auto& i : items) rove::write_object(ar, *i);
  }
  void load_payload(rove::InArchive& ar, std::uint8_t) override {
    ar >> grid;
    const std::uint32_t n = ar.read_length("items", 7);
    items.clear();
    for (std::uint32_t i = 0; i < n; ++i) items.push_back(rove::read_object(ar));
  }
};

const rove::Registrar<Scan> kScan;
const rove::Registrar<Frame> kFrame;

rove::ArchiveLimits fuzz_limits() {
  rove::ArchiveLimits l;
  l.max_length = std::uint64_t{1} << 20;
  l.max_nesting = 32;
  return l;
}

std::vector<std::byte> write_back(const rove::Serializable& obj) {
  rove::MemoryOutStream out;
  rove::OutArchive ar(out);
  rove::write_object(ar, obj);
  return out.take();
}

void fuzz_objects(std::span<const std::byte> data) {
  rove::MemoryInStream in(data, "<fuzz>");
  rove::InArchive ar(in, fuzz_limits());
  while (!ar.at_end()) {
    std::unique_ptr<rove::Serializable> obj = rove::read_object(ar);
    if (!obj) die("read_object returned null");
    const auto bytes = write_back(*obj);
    rove::MemoryInStream again(std::span<const std::byte>(bytes), "<rewrite>");
    rove::InArchive ar2(again, fuzz_limits());
    std::unique_ptr<rove::Serializable> copy;
    try {
      copy = rove::read_object(ar2);
    } catch (const rove::ParseError&) {
      die("an object read back fails to load after writing it");
    }
    if (!ar2.at_end()) die("rewritten object has trailing bytes");
    if (write_back(*copy) != bytes) die("object does not round-trip");
  }
}

using MrptValue = std::variant<std::monostate, Eigen::MatrixXd, std::vector<double>>;

const rove::MrptClassReaders<MrptValue>& mrpt_readers() {
  static const auto* readers = [] {
    auto* r = new rove::MrptClassReaders<MrptValue>();
    r->add("CMatrixD", [](rove::InArchive& ar, const rove::MrptObjectHeader& h) -> MrptValue {
      if (h.version != 0) rove::throw_unknown_mrpt_version(ar, h);
      return rove::read_mrpt_matrix<double>(ar, "CMatrixD");
    });
    r->add("CPose3D", [r](rove::InArchive& ar, const rove::MrptObjectHeader& h) -> MrptValue {
      if (h.version > 1) rove::throw_unknown_mrpt_version(ar, h);
      return r->read_object(ar);
    });
    r->add("CThing", [r](rove::InArchive& ar, const rove::MrptObjectHeader&) -> MrptValue {
      (void)rove::read_mrpt_string(ar, "name");
      (void)rove::read_mrpt_bool_vector(ar, "valid");
      (void)rove::read_mrpt_string_vector(ar, "labels");
      const std::uint32_t n = rove::read_mrpt_container_preamble(ar, "std::vector", {"double"}, "v");
      std::vector<double> v;
      ar.append_scalars(v, n, "v");
      (void)r->read_object(ar);
      return v;
    });
    return r;
  }();
  return *readers;
}

void fuzz_mrpt(std::span<const std::byte> data) {
  {
    rove::MemoryInStream in(data, "<fuzz>");
    rove::InArchive ar(in, fuzz_limits());
    while (!ar.at_end()) (void)mrpt_readers().read_object(ar);
  }
  {
    // Headers alone, as a reader scanning a rawlog's first object would.
    rove::MemoryInStream in(data, "<fuzz>");
    rove::InArchive ar(in, fuzz_limits());
    const rove::MrptObjectHeader h = rove::read_mrpt_object_header(ar);
    if (h.offset != 0) die("first header not at offset 0");
    if (h.class_name.size() > 120) die("class name above MRPT's limit accepted");
    (void)rove::read_mrpt_vector<float>(ar, "floats");
    rove::expect_mrpt_end_marker(ar, h);
  }
}

void fuzz_values(std::span<const std::byte> data) {
  using Value = std::tuple<std::vector<std::map<std::string, std::optional<double>>>,
                           std::array<Eigen::Vector2f, 2>, std::multimap<std::int8_t, bool>,
                           Eigen::Matrix<std::int16_t, Eigen::Dynamic, 3>>;
  rove::MemoryInStream in(data, "<fuzz>");
  rove::InArchive ar(in, fuzz_limits());
  Value v;
  ar >> v;
  rove::MemoryOutStream out;
  rove::OutArchive oa(out);
  oa << v;
  const auto consumed = static_cast<std::size_t>(ar.offset());
  if (consumed > data.size()) die("offset beyond the input");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* bytes, std::size_t size) {
  if (size == 0) return 0;
  const std::span<const std::byte> data(reinterpret_cast<const std::byte*>(bytes) + 1, size - 1);
  try {
    switch (bytes[0] % 3) {
      case 0: fuzz_objects(data); break;
      case 1: fuzz_mrpt(data); break;
      default: fuzz_values(data); break;
    }
  } catch (const rove::ParseError& e) {
    if (!e.location().offset || *e.location().offset > data.size()) die("error offset out of range");
  }
  return 0;
}
