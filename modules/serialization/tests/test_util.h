#pragma once
// Helpers shared by the serialization tests.

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include <gtest/gtest.h>
#include <unistd.h>

#include "rove/serialization/archive.h"
#include "rove/serialization/memory_stream.h"

namespace rove::test {

inline std::vector<std::byte> from_hex(std::string_view hex) {
  std::vector<std::byte> out;
  int hi = -1;
  for (const char c : hex) {
    int v = -1;
    if (c >= '0' && c <= '9') v = c - '0';
    if (c >= 'a' && c <= 'f') v = c - 'a' + 10;
    if (c >= 'A' && c <= 'F') v = c - 'A' + 10;
    if (v < 0) continue;  // spaces separate bytes for readability
    if (hi < 0) {
      hi = v;
    } else {
      out.push_back(static_cast<std::byte>(hi * 16 + v));
      hi = -1;
    }
  }
  EXPECT_LT(hi, 0) << "odd number of hex digits";
  return out;
}

inline std::string to_hex(const std::vector<std::byte>& bytes) {
  static constexpr char kDigits[] = "0123456789abcdef";
  std::string s;
  for (std::size_t i = 0; i < bytes.size(); ++i) {
    if (i > 0) s += ' ';
    const auto b = std::to_integer<unsigned>(bytes[i]);
    s += kDigits[b >> 4];
    s += kDigits[b & 15];
  }
  return s;
}

/// The bytes `save` writes for `value`.
template <typename T>
std::vector<std::byte> bytes_of(const T& value) {
  MemoryOutStream out;
  OutArchive ar(out);
  ar << value;
  return out.take();
}

/// Loads a T from `bytes`, requiring every byte to be consumed.
template <typename T>
T load_from(const std::vector<std::byte>& bytes) {
  MemoryInStream in(std::span<const std::byte>(bytes), "<test>");
  InArchive ar(in);
  T value{};
  ar >> value;
  EXPECT_TRUE(ar.at_end()) << "bytes left after load";
  return value;
}

template <typename T>
T round_trip(const T& value) {
  return load_from<T>(bytes_of(value));
}

/// A fresh directory for one test's files, removed by the destructor.
class TempDir {
 public:
  TempDir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    path_ = std::filesystem::temp_directory_path() /
            ("rove_ser_" + std::to_string(::getpid()) + "_" + info->test_suite_name() + "_" +
             info->name());
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  std::string file(const std::string& name) const { return (path_ / name).string(); }

 private:
  std::filesystem::path path_;
};

}  // namespace rove::test
