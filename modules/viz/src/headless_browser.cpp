#include "rove/viz/headless_browser.h"

#include <fmt/format.h>
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cctype>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

#include "rove/core/error.h"
#include "rove/core/files.h"
#include "rove/core/interrupt.h"

extern char** environ;

namespace rove {

namespace fs = std::filesystem;

namespace {

// A temporary folder removed when it goes out of scope.
class TempDir {
 public:
  TempDir() {
    std::string pattern = (fs::temp_directory_path() / "rove-chromium-XXXXXX").string();
    if (mkdtemp(pattern.data()) == nullptr) throw IoError(pattern, "cannot create a temporary folder");
    path_ = pattern;
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

std::string tail_of_file(const fs::path& p, std::size_t max_chars) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  std::string s = ss.str();
  if (s.size() > max_chars) s = "..." + s.substr(s.size() - max_chars);
  return printable(s);
}

// Runs Chromium with `args`, returning its standard output. Its standard
// error goes to a file in the profile folder, quoted when it fails.
std::string run_chromium(const HeadlessOptions& o, std::vector<std::string> args) {
  const std::string exe = o.chromium.empty() ? find_chromium() : o.chromium;
  const TempDir profile;
  const fs::path err_path = profile.path() / "stderr.txt";
  std::vector<std::string> argv = {exe,
                                   "--headless",
                                   "--no-sandbox",
                                   "--no-first-run",
                                   "--disable-dev-shm-usage",
                                   "--enable-unsafe-swiftshader",
                                   "--hide-scrollbars",
                                   "--mute-audio",
                                   "--user-data-dir=" + (profile.path() / "profile").string(),
                                   fmt::format("--window-size={},{}", o.width, o.height),
                                   fmt::format("--virtual-time-budget={}", o.virtual_time_ms)};
  argv.insert(argv.end(), args.begin(), args.end());
  std::vector<char*> cargv;
  for (auto& a : argv) cargv.push_back(a.data());
  cargv.push_back(nullptr);

  int out_pipe[2];
  if (pipe(out_pipe) != 0) throw IoError(exe, "cannot create a pipe");
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, out_pipe[1], STDOUT_FILENO);
  posix_spawn_file_actions_addclose(&actions, out_pipe[0]);
  posix_spawn_file_actions_addclose(&actions, out_pipe[1]);
  posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, err_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
  posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  pid_t pid = 0;
  const int rc = posix_spawn(&pid, exe.c_str(), &actions, nullptr, cargv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  close(out_pipe[1]);
  if (rc != 0) {
    close(out_pipe[0]);
    throw IoError(exe, fmt::format("cannot start Chromium: {}", std::strerror(rc)));
  }
  std::string out;
  const auto start = std::chrono::steady_clock::now();
  bool timed_out = false, stop = false;
  char buf[65536];
  while (!stop) {
    pollfd p{out_pipe[0], POLLIN, 0};
    const int ready = poll(&p, 1, 200);
    if (ready > 0) {
      const ssize_t n = read(out_pipe[0], buf, sizeof buf);
      if (n > 0) out.append(buf, static_cast<std::size_t>(n));
      if (n == 0 || (n < 0 && errno != EINTR)) stop = true;
    }
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (!stop && (elapsed > o.timeout_s || interrupted())) {
      timed_out = elapsed > o.timeout_s;
      kill(pid, SIGKILL);
      stop = true;
    }
  }
  close(out_pipe[0]);
  int status = 0;
  while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  throw_if_interrupted();
  if (timed_out) throw IoError(exe, fmt::format("Chromium took longer than {} s and was stopped", o.timeout_s));
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    throw IoError(exe, fmt::format("Chromium failed (status {}): {}", status, tail_of_file(err_path, 600)));
  }
  return out;
}

}  // namespace

std::string find_chromium() {
  const char* path_env = std::getenv("PATH");
  const std::string path = path_env != nullptr ? path_env : "/usr/bin:/bin";
  for (const char* name : {"chromium", "chromium-browser", "google-chrome"}) {
    std::size_t from = 0;
    while (from <= path.size()) {
      const std::size_t to = std::min(path.find(':', from), path.size());
      const fs::path candidate = fs::path(path.substr(from, to - from)) / name;
      if (to > from && access(candidate.c_str(), X_OK) == 0) return candidate.string();
      from = to + 1;
    }
  }
  throw IoError("chromium", "no headless browser found on PATH: install Debian's chromium (scripts/install-deps does)");
}

std::string headless_dump_dom(const std::string& url, const HeadlessOptions& options) {
  return run_chromium(options, {"--dump-dom", url});
}

void headless_screenshot(const std::string& url, const std::string& png_path, const HeadlessOptions& options) {
  write_file_atomically(png_path, [&](const fs::path& tmp) {
    // Chromium picks the image format by the extension: give it ".png".
    const fs::path shot = fs::absolute(tmp).string() + ".png";
    try {
      run_chromium(options, {"--screenshot=" + shot.string(), url});
      std::error_code ec;
      if (!fs::is_regular_file(shot, ec) || fs::file_size(shot, ec) == 0) {
        throw IoError(png_path, "Chromium wrote no screenshot");
      }
      fs::rename(shot, tmp);
    } catch (...) {
      std::error_code ec;
      fs::remove(shot, ec);
      throw;
    }
  });
}

std::string file_url(const std::string& path) {
  const std::string abs = fs::absolute(path).lexically_normal().string();
  std::string url = "file://";
  for (unsigned char c : abs) {
    if (std::isalnum(c) || c == '/' || c == '-' || c == '_' || c == '.' || c == '~') {
      url += static_cast<char>(c);
    } else {
      url += fmt::format("%{:02X}", c);
    }
  }
  return url;
}

}  // namespace rove
