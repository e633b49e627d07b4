#pragma once
/// \file
/// Progress reporting for long jobs. On a terminal, a one-line bar with
/// percentage, rate and ETA, redrawn in place with '\r'; otherwise (a log
/// file, a pipe, a test) plain lines, one each time progress crosses a
/// multiple of 10% and, optionally, every N seconds:
///
///   rove::Progress p(scans.size(), "ICP-SLAM");
///   for (...) { ...; p.advance(); }
///   p.finish();
///
/// With an unknown total only counts and rates are shown.

#include <cstdint>
#include <functional>
#include <iostream>
#include <mutex>
#include <optional>
#include <string>

namespace rove {

/// How Progress writes.
enum class ProgressMode {
  Auto,  ///< Bar if the stream is std::cerr/std::clog (std::cout) and stderr (stdout) is a terminal, else Lines
  Bar,   ///< one line redrawn with '\r'
  Lines  ///< plain lines, for logs and pipes
};

/// Settings of a Progress; the defaults suit interactive use.
struct ProgressOptions {
  ProgressMode mode = ProgressMode::Auto;
  /// Lines: a line each time the percentage crosses a multiple of this
  /// (known total only). Must be in (0, 100].
  double line_percent_step = 10.0;
  /// Lines: also a line when this many seconds passed since the last one
  /// and the count changed; 0 disables. The only trigger for an unknown total.
  double line_interval_seconds = 30.0;
  /// Bar: minimum seconds between redraws.
  double bar_interval_seconds = 0.1;
  /// Bar: width of the bar in characters (>= 1).
  int bar_width = 30;
  /// What is counted, shown after counts and in rates ("it/s").
  std::string unit = "it";
  /// Monotonic time in seconds; steady_clock if empty. Inject one to make
  /// output deterministic in tests.
  std::function<double()> clock;
};

/// Reports the progress of a job of `total` steps (or unknown) to a stream.
/// Thread-safe: any thread may advance(). The stream must outlive it.
class Progress {
 public:
  /// Starts a report of `total` steps (nullopt: unknown) labelled `label`.
  Progress(std::optional<std::uint64_t> total, std::string label, std::ostream& os = std::cerr,
           ProgressMode mode = ProgressMode::Auto);
  /// As above with full options. Precondition (InvalidArgument): options
  /// are in their documented ranges.
  Progress(std::optional<std::uint64_t> total, std::string label, std::ostream& os,
           ProgressOptions options);
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;
  /// Calls finish() if it was not called.
  ~Progress();

  /// Adds `n` steps. Precondition (InvalidArgument): the count stays
  /// <= total when the total is known.
  void advance(std::uint64_t n = 1);
  /// Sets the count of steps done (may go down, e.g. on retry); same
  /// precondition as advance().
  void set(std::uint64_t done);
  /// Prints the final line (count, elapsed time, mean rate). Later calls,
  /// and advance()/set() after it, do nothing.
  void finish();

  /// Steps done so far.
  std::uint64_t done() const;
  /// The mode in use (Auto resolved to Bar or Lines).
  ProgressMode mode() const noexcept { return options_.mode; }

 private:
  double now() const;
  void update(std::uint64_t done);
  void emit_line(double t);
  void draw_bar(double t, bool final);
  std::string stats_text(double t) const;

  std::optional<std::uint64_t> total_;
  std::string label_;
  std::ostream& os_;
  ProgressOptions options_;
  mutable std::mutex mutex_;
  std::uint64_t done_ = 0;
  double start_ = 0.0;
  double last_output_ = 0.0;
  std::uint64_t done_at_last_line_ = 0;
  double next_percent_ = 0.0;
  bool drawn_ = false;
  std::size_t last_bar_length_ = 0;
  bool finished_ = false;
};

/// Seconds as "12.3 s" below a minute, else "H:MM:SS".
std::string format_elapsed(double seconds);

}  // namespace rove
