#include "rove/serialization/input_file.h"

#include <array>
#include <cerrno>
#include <cstdio>
#include <cstring>

#include "rove/core/error.h"
#include "rove/serialization/file_stream.h"
#include "rove/serialization/gzip_stream.h"

namespace rove {

bool is_gzip_file(const std::string& path) {
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (f == nullptr) {
    throw IoError(path, std::string("cannot open for reading: ") + std::strerror(errno));
  }
  std::array<unsigned char, 2> magic{};
  const std::size_t n = std::fread(magic.data(), 1, magic.size(), f);
  const bool failed = std::ferror(f) != 0;
  std::fclose(f);
  if (failed) throw IoError(path, "read failed");
  return n == 2 && magic[0] == 0x1f && magic[1] == 0x8b;
}

std::unique_ptr<InStream> open_input_file(const std::string& path) {
  if (is_gzip_file(path)) return std::make_unique<GzipFileInStream>(path);
  return std::make_unique<FileInStream>(path);
}

std::unique_ptr<OutStream> open_output_file(const std::string& path,
                                            FileCompression compression) {
  switch (compression) {
    case FileCompression::None:
      return std::make_unique<FileOutStream>(path);
    case FileCompression::Gzip:
      return std::make_unique<GzipFileOutStream>(path, 6);
  }
  throw InvalidArgument("open_output_file: unknown FileCompression value");
}

}  // namespace rove
