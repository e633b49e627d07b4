#pragma once
/// \file
/// rove's exception types. Every error rove throws derives from rove::Error,
/// which carries a message and the chain of places the exception passed
/// through on its way up (added by ROVE_TRACE_BEGIN / ROVE_TRACE_END, the
/// counterpart of MRPT's MRPT_START / MRPT_END).
///
/// Two families, following the convention in ARCHITECTURE.md:
///  - a violated precondition is a bug in the caller: InvalidArgument
///    (thrown by the ROVE_CHECK* macros with the expression and the values);
///  - bad input from outside (a file, a config, NaN in data) is expected:
///    ParseError / IoError / ConfigError name the file and the line, offset or
///    field involved.

#include <cstdint>
#include <exception>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace rove {

/// Where an exception was raised or passed through: function, file, line.
struct SourceFrame {
  std::string function;
  std::string file;
  int line = 0;
};

/// Base of every rove exception. what() returns the message followed by one
/// "  at function (file:line)" line per frame, innermost first.
class Error : public std::exception {
 public:
  explicit Error(std::string message);
  Error(std::string message, SourceFrame origin);

  /// The message without the trace.
  const std::string& message() const noexcept { return message_; }
  /// The frames the exception passed through, innermost first.
  const std::vector<SourceFrame>& trace() const noexcept { return trace_; }
  /// Appends a frame; used by ROVE_TRACE_END while unwinding.
  void add_frame(SourceFrame frame);
  const char* what() const noexcept override { return what_.c_str(); }

 private:
  void rebuild_what();
  std::string message_;
  std::vector<SourceFrame> trace_;
  std::string what_;
};

/// A precondition was violated: the caller passed something the function's
/// contract excludes. Thrown by the ROVE_CHECK* macros.
class InvalidArgument : public Error {
 public:
  using Error::Error;
};

/// A numerical failure that the input could not have excluded beforehand
/// (non-positive-definite matrix, diverging iteration, NaN produced).
class NumericError : public Error {
 public:
  using Error::Error;
};

/// Reading or writing a file or stream failed at the operating-system level.
class IoError : public Error {
 public:
  IoError(std::string path, std::string what_failed);
  const std::string& path() const noexcept { return path_; }

 private:
  std::string path_;
};

/// Malformed outside input. Names the source (file path or "<string>"), and
/// the line (text formats, 1-based) or byte offset (binary formats) and the
/// field when known.
class ParseError : public Error {
 public:
  struct Location {
    std::string source;                 ///< file path, or a description of the stream
    std::optional<std::size_t> line;    ///< 1-based line, text formats
    std::optional<std::uint64_t> offset;///< byte offset, binary formats
    std::string field;                  ///< field, key or class involved, if any
  };
  ParseError(Location where, std::string problem);
  const Location& location() const noexcept { return where_; }
  const std::string& problem() const noexcept { return problem_; }

 private:
  Location where_;
  std::string problem_;
};

/// A configuration value is missing, malformed or unknown. Names the file,
/// section and key.
class ConfigError : public Error {
 public:
  ConfigError(std::string file, std::string section, std::string key, std::string problem);
  const std::string& file() const noexcept { return file_; }
  const std::string& section() const noexcept { return section_; }
  const std::string& key() const noexcept { return key_; }

 private:
  std::string file_, section_, key_;
};

/// A request would exceed a stated resource limit (the memory budget, a
/// thread cap, a file-size limit). The message names what asked for it.
class ResourceError : public Error {
 public:
  using Error::Error;
};

namespace detail {
/// Rethrows the exception in flight with one more frame. A rove::Error keeps
/// its type; any other std::exception becomes a rove::Error that quotes it.
[[noreturn]] void rethrow_with_frame(SourceFrame frame);
}  // namespace detail

}  // namespace rove

/// Opens a block whose exceptions collect the enclosing function's frame.
#define ROVE_TRACE_BEGIN try {
/// Closes a ROVE_TRACE_BEGIN block: a rove::Error gets this function's frame
/// added and continues; another std::exception is wrapped into rove::Error.
#define ROVE_TRACE_END                                                     \
  }                                                                        \
  catch (...) {                                                            \
    ::rove::detail::rethrow_with_frame({__func__, __FILE__, __LINE__});    \
  }
