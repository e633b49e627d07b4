#pragma once
/// \file
/// Safe file handling for everything rove writes and reads from outside:
///  - outputs are written to a temporary sibling and renamed over the target
///    only when complete, so an error or Ctrl-C never leaves a partial file
///    that looks finished, and a failed run never truncates an older result;
///  - an output that resolves to one of the inputs (same device and inode, or
///    the same path) is refused before anything is opened;
///  - inputs must be regular files (a directory, /dev/zero or a FIFO is
///    refused with its path), and text inputs are read with a size limit.

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

namespace rove {

/// Writes `path` atomically. `write(tmp)` must create and fill the file at
/// `tmp`, a fresh name in the same folder as `path`; when it returns, `tmp` is
/// flushed and renamed over `path`. If `write` throws (or the rename fails),
/// `tmp` is removed and the exception propagates: `path` keeps its old content.
/// Throws rove::IoError naming `path` when the folder does not exist or is not
/// writable.
void write_file_atomically(const std::filesystem::path& path,
                           const std::function<void(const std::filesystem::path& tmp)>& write);

/// Writes `bytes` to `path` atomically (see write_file_atomically).
void write_text_file_atomically(const std::filesystem::path& path, std::string_view bytes);

/// A file being written under a temporary name beside its final path. `commit()`
/// flushes, closes and renames it; destroying it uncommitted removes the
/// temporary file. Not copyable.
class AtomicOutputFile {
 public:
  /// Opens a temporary sibling of `path` for binary writing.
  /// Throws rove::IoError naming `path` when it cannot be created.
  explicit AtomicOutputFile(std::filesystem::path path);
  AtomicOutputFile(const AtomicOutputFile&) = delete;
  AtomicOutputFile& operator=(const AtomicOutputFile&) = delete;
  ~AtomicOutputFile();

  /// The open temporary file (valid until commit()).
  std::FILE* file() const noexcept { return file_; }
  /// Writes bytes; throws rove::IoError naming the final path on failure.
  void write(std::string_view bytes);
  /// Flushes, closes and renames onto the final path. Throws rove::IoError.
  void commit();
  const std::filesystem::path& path() const noexcept { return path_; }
  const std::filesystem::path& temporary_path() const noexcept { return tmp_; }

 private:
  std::filesystem::path path_, tmp_;
  std::FILE* file_ = nullptr;
  bool committed_ = false;
};

/// A fresh temporary name for `path` in the same folder (".name.rove-tmp-PID-N").
std::filesystem::path temporary_sibling(const std::filesystem::path& path);

/// Refuses, with rove::IoError naming both, any output that resolves to one of
/// the inputs (the same device and inode when both exist, the same normalized
/// absolute path otherwise), or to another output; and any output that is an
/// existing directory or a non-regular file (a device, a FIFO).
void check_outputs_distinct(const std::vector<std::filesystem::path>& inputs,
                            const std::vector<std::filesystem::path>& outputs);

/// Refuses, with rove::IoError naming it, a path that does not exist, is a
/// directory, or is not a regular file (devices, FIFOs, sockets). `what`
/// describes the file's role in the message ("config file", "graph").
void check_regular_input(const std::filesystem::path& path, std::string_view what = "input");

/// Reads a whole text or binary input of at most `max_bytes` (after
/// check_regular_input). Larger files are refused with their size and the
/// limit, never read into memory first.
std::string read_input_file(const std::filesystem::path& path, std::uint64_t max_bytes,
                            std::string_view what = "input");

/// Default size limit of read_input_file for text inputs a person writes
/// (configuration files, YAML): 64 MiB.
inline constexpr std::uint64_t kMaxTextInputBytes = 64ull << 20;

/// A path for messages: printable, with control and non-UTF-8 bytes escaped as
/// \xNN, so a hostile file name cannot write to the terminal.
std::string printable(std::string_view text);

}  // namespace rove
