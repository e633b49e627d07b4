#pragma once
/// \file
/// Pages rendered without a display, through headless Chromium (Debian's
/// `chromium`): the DOM after the page settled (for scripts and tests) and
/// screenshots (`rove view --screenshot`). WebGL runs on Chromium's
/// software renderer (SwiftShader), so no GPU is needed. Chromium runs with
/// --no-sandbox (the page is rove's own and the run is short), a fresh
/// profile folder removed afterwards, and a virtual-time budget: the page
/// loads and renders, then Chromium dumps or shoots.

#include <string>

namespace rove {

/// The Chromium executable: the first of chromium, chromium-browser,
/// google-chrome on PATH. Throws IoError naming Debian's `chromium` package
/// when none is found.
std::string find_chromium();

/// Options of the headless runs.
struct HeadlessOptions {
  std::string chromium;       ///< executable; empty: find_chromium()
  int width = 1280;           ///< window width, pixels
  int height = 800;           ///< window height, pixels
  /// Virtual time the page gets before the dump or the screenshot,
  /// milliseconds (loading a large scene takes more).
  int virtual_time_ms = 30'000;
  /// Wall-clock limit, seconds: Chromium is killed after it (IoError).
  double timeout_s = 300.0;
};

/// Loads `url` (http://... or file://...) and returns the DOM as HTML.
/// Throws IoError if Chromium cannot be started, fails, or times out;
/// Interrupted on Ctrl-C (when the handler is installed).
std::string headless_dump_dom(const std::string& url, const HeadlessOptions& options = {});

/// Loads `url` and writes a PNG screenshot of the window to `png_path`
/// (atomically: Chromium writes a temporary sibling that is renamed).
/// Throws as headless_dump_dom, and IoError when no image was written.
void headless_screenshot(const std::string& url, const std::string& png_path, const HeadlessOptions& options = {});

/// file://<absolute path> of a local file, percent-encoding what a URL
/// cannot hold.
std::string file_url(const std::string& path);

}  // namespace rove
