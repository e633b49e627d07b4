#pragma once
/// \file
/// What every rove command tells its user, the same way everywhere:
///  - exit status: kExitOk (0) success; kExitError (1) an error, nothing
///    trustworthy written; kExitUsage (2) a bad command line; kExitIssues (3)
///    the command ran to its end and wrote its outputs, but the result has
///    issues (not converged, nothing accepted, an empty selection) that the
///    summary lists; kExitInterrupted (130) stopped by Ctrl-C, complete
///    outputs kept;
///  - issues: one line each on stderr ("rove: warning: <code>: <message>")
///    and, with --json, an "issues" array of {"code", "message"} objects.

#include <fmt/format.h>

#include <cstdio>
#include <string>
#include <vector>

#include "rove/core/json.h"

namespace rove::cli {

inline constexpr int kExitOk = 0;
inline constexpr int kExitError = 1;
inline constexpr int kExitUsage = 2;
inline constexpr int kExitIssues = 3;
inline constexpr int kExitInterrupted = 130;

/// Something the user must know about a result that was written anyway.
struct Issue {
  std::string code;     ///< stable identifier: "max-iterations", "not-converged", ...
  std::string message;  ///< one line for a person
};

/// Thrown by a command that finished and wrote its outputs but found issues
/// (already printed); main() turns it into kExitIssues.
struct IssuesExit {
  int code = kExitIssues;
};

/// Prints each issue as "rove: warning: <code>: <message>" on stderr.
inline void print_issues(const std::vector<Issue>& issues) {
  for (const auto& i : issues) fmt::print(stderr, "rove: warning: {}: {}\n", i.code, i.message);
}

/// Writes `"issues": [...]` into an open JSON object.
inline void write_issues(JsonWriter& j, const std::vector<Issue>& issues) {
  j.key("issues").begin_array();
  for (const auto& i : issues) {
    j.begin_object().key("code").value(i.code).key("message").value(i.message).end_object();
  }
  j.end_array();
}

/// Ends a command: prints the issues, then throws IssuesExit when there are any.
inline void finish(const std::vector<Issue>& issues) {
  print_issues(issues);
  if (!issues.empty()) throw IssuesExit{};
}

}  // namespace rove::cli
