#pragma once
/// \file
/// Opening files whose compression is found by looking at them.

#include <memory>
#include <string>

#include "rove/serialization/stream.h"

namespace rove {

/// True if the file at `path` starts with the gzip magic bytes 1f 8b.
/// Throws rove::IoError if the file cannot be opened.
bool is_gzip_file(const std::string& path);

/// Opens `path` for reading: a GzipFileInStream when it starts with the gzip
/// magic (1f 8b), a FileInStream otherwise, so plain and .gz files load alike.
/// Offsets in errors are then offsets in the decompressed data.
/// Throws rove::IoError with the path if the file cannot be opened.
std::unique_ptr<InStream> open_input_file(const std::string& path);

/// How open_output_file stores data.
enum class FileCompression {
  None,  ///< plain bytes
  Gzip,  ///< gzip, level 6
};

/// Creates (or truncates) `path` for writing with the given compression.
/// Throws rove::IoError with the path if the file cannot be created.
std::unique_ptr<OutStream> open_output_file(const std::string& path,
                                            FileCompression compression);

}  // namespace rove
