#include "rove/core/files.h"

#include <fmt/format.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>

#include "rove/core/error.h"
#include "utf8.h"

namespace fs = std::filesystem;

namespace rove {
namespace {

std::string errno_text() { return std::strerror(errno); }

// Creates `tmp` exclusively so two writers never share a temporary file.
std::FILE* create_exclusive(const fs::path& tmp) {
  return std::fopen(tmp.c_str(), "wbx");
}

void flush_and_close(std::FILE* f, const fs::path& final_path) {
  const bool ok = std::fflush(f) == 0 && fsync(fileno(f)) == 0;
  const int err = errno;
  const bool closed = std::fclose(f) == 0;
  if (!ok || !closed) {
    errno = ok ? errno : err;
    throw IoError(printable(final_path.string()), "write failed: " + errno_text());
  }
}

void rename_over(const fs::path& tmp, const fs::path& path) {
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    const std::string why = errno_text();
    std::remove(tmp.c_str());
    throw IoError(printable(path.string()), "cannot replace with the finished file: " + why);
  }
}

// Absolute, lexically normal form, with symlinks resolved as far as they exist.
fs::path canonical_or_normal(const fs::path& p) {
  std::error_code ec;
  fs::path c = fs::weakly_canonical(p, ec);
  if (ec) c = fs::absolute(p, ec).lexically_normal();
  return c;
}

struct Identity {
  bool exists = false;
  dev_t dev = 0;
  ino_t ino = 0;
  fs::path normal;
};

Identity identify(const fs::path& p) {
  Identity id;
  struct stat st {};
  if (::stat(p.c_str(), &st) == 0) {
    id.exists = true;
    id.dev = st.st_dev;
    id.ino = st.st_ino;
  }
  id.normal = canonical_or_normal(p);
  return id;
}

bool same_file(const Identity& a, const Identity& b) {
  if (a.exists && b.exists) return a.dev == b.dev && a.ino == b.ino;
  return a.normal == b.normal;
}

// Refuses an output whose folder is missing or which is itself a directory.
void check_output_location(const fs::path& path) {
  if (path.empty()) throw IoError("", "empty output path");
  const fs::path dir = path.has_parent_path() ? path.parent_path() : fs::path(".");
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) {
    throw IoError(printable(path.string()),
                  fmt::format("cannot write: folder '{}' does not exist", printable(dir.string())));
  }
  if (fs::is_directory(path, ec)) {
    throw IoError(printable(path.string()), "cannot write: it is a directory");
  }
}

}  // namespace

std::string printable(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  std::size_t i = 0;
  while (i < text.size()) {
    const auto c = static_cast<unsigned char>(text[i]);
    // Printable ASCII or a well-formed multi-byte sequence is kept as is.
    const std::size_t len = c < 0x80 ? (c >= 0x20 && c < 0x7f ? 1 : 0)
                                     : detail::utf8_sequence_length(text, i);
    const bool ok = len > 0;
    if (ok) {
      out.append(text.substr(i, len));
      i += len;
    } else {
      out += fmt::format("\\x{:02x}", c);
      ++i;
    }
  }
  return out;
}

fs::path temporary_sibling(const fs::path& path) {
  static std::atomic<unsigned> counter{0};
  const fs::path dir = path.has_parent_path() ? path.parent_path() : fs::path(".");
  return dir / fmt::format(".{}.rove-tmp-{}-{}", path.filename().string(),
                           static_cast<long>(getpid()), counter.fetch_add(1));
}

void write_file_atomically(const fs::path& path,
                           const std::function<void(const fs::path& tmp)>& write) {
  check_output_location(path);
  const fs::path tmp = temporary_sibling(path);
  std::error_code ec;
  try {
    write(tmp);
    if (!fs::exists(tmp, ec)) {
      throw IoError(printable(path.string()), "the writer produced no file");
    }
    rename_over(tmp, path);
  } catch (...) {
    std::remove(tmp.c_str());
    throw;
  }
}

void write_text_file_atomically(const fs::path& path, std::string_view bytes) {
  AtomicOutputFile out(path);
  out.write(bytes);
  out.commit();
}

AtomicOutputFile::AtomicOutputFile(fs::path path) : path_(std::move(path)) {
  check_output_location(path_);
  tmp_ = temporary_sibling(path_);
  file_ = create_exclusive(tmp_);
  if (file_ == nullptr) {
    throw IoError(printable(path_.string()), "cannot create: " + errno_text());
  }
}

AtomicOutputFile::~AtomicOutputFile() {
  if (!committed_) {
    if (file_ != nullptr) std::fclose(file_);
    std::remove(tmp_.c_str());
  }
}

void AtomicOutputFile::write(std::string_view bytes) {
  if (file_ == nullptr) throw IoError(printable(path_.string()), "write after commit");
  if (!bytes.empty() && std::fwrite(bytes.data(), 1, bytes.size(), file_) != bytes.size()) {
    throw IoError(printable(path_.string()), "write failed: " + errno_text());
  }
}

void AtomicOutputFile::commit() {
  if (committed_) return;
  std::FILE* f = file_;
  file_ = nullptr;
  flush_and_close(f, path_);
  rename_over(tmp_, path_);
  committed_ = true;
}

void check_outputs_distinct(const std::vector<fs::path>& inputs,
                            const std::vector<fs::path>& outputs) {
  std::vector<Identity> in_ids;
  in_ids.reserve(inputs.size());
  for (const auto& p : inputs) in_ids.push_back(identify(p));
  std::vector<Identity> out_ids;
  for (std::size_t o = 0; o < outputs.size(); ++o) {
    const fs::path& out = outputs[o];
    if (out.empty()) continue;
    const Identity id = identify(out);
    struct stat st {};
    if (id.exists && ::stat(out.c_str(), &st) == 0 && !S_ISREG(st.st_mode)) {
      throw IoError(printable(out.string()),
                    S_ISDIR(st.st_mode) ? "output is a directory; name a file"
                                        : "output is not a regular file (a device or a FIFO)");
    }
    for (std::size_t i = 0; i < inputs.size(); ++i) {
      if (same_file(id, in_ids[i])) {
        throw IoError(printable(out.string()),
                      fmt::format("refusing to write over the input '{}': choose another output",
                                  printable(inputs[i].string())));
      }
    }
    for (const auto& prev : out_ids) {
      if (same_file(id, prev)) {
        throw IoError(printable(out.string()), "named twice as an output");
      }
    }
    out_ids.push_back(id);
  }
}

void check_regular_input(const fs::path& path, std::string_view what) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) {
    throw IoError(printable(path.string()), fmt::format("cannot open {}: {}", what, errno_text()));
  }
  if (S_ISDIR(st.st_mode)) {
    throw IoError(printable(path.string()), fmt::format("{} is a directory, not a file", what));
  }
  if (!S_ISREG(st.st_mode)) {
    throw IoError(printable(path.string()),
                  fmt::format("{} is not a regular file (a device, FIFO or socket); rove reads "
                              "only regular files",
                              what));
  }
}

std::string read_input_file(const fs::path& path, std::uint64_t max_bytes, std::string_view what) {
  check_regular_input(path, what);
  std::error_code ec;
  const std::uint64_t size = fs::file_size(path, ec);
  if (ec) throw IoError(printable(path.string()), "cannot read its size: " + ec.message());
  if (size > max_bytes) {
    throw IoError(printable(path.string()),
                  fmt::format("{} is {} bytes, over the limit of {} bytes for this kind of file",
                              what, size, max_bytes));
  }
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (f == nullptr) {
    throw IoError(printable(path.string()), fmt::format("cannot open {}: {}", what, errno_text()));
  }
  std::string data(static_cast<std::size_t>(size), '\0');
  const std::size_t n = size == 0 ? 0 : std::fread(data.data(), 1, data.size(), f);
  const bool failed = std::ferror(f) != 0;
  std::fclose(f);
  if (failed) throw IoError(printable(path.string()), "read failed");
  data.resize(n);
  return data;
}

}  // namespace rove
