// `rove view FILE...`: one 3D scene from rove's files and output folders,
// served to a browser on localhost, exported as glTF, as one HTML page, or
// rendered to a PNG through headless Chromium.

#include <fmt/format.h>

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "commands.h"
#include "report.h"
#include "rove/core/error.h"
#include "rove/core/files.h"
#include "rove/core/timer.h"
#include "rove/viz/glb.h"
#include "rove/viz/headless_browser.h"
#include "rove/viz/scene_files.h"
#include "rove/viz/viewer_page.h"
#include "rove/viz/viewer_server.h"

namespace rove::cli {

namespace {

namespace fs = std::filesystem;

struct ViewOptions {
  std::vector<std::string> inputs;
  int port = 8080;
  std::string host = "127.0.0.1";
  std::string glb, html, screenshot;
  std::string size = "1280x800";
  std::size_t max_points = 4'000'000;
  std::size_t lod_points = 1'000'000;
  std::string three_dir = std::string(kDefaultThreeDir);
  bool serve = false;
  bool measure = false;
};

std::pair<int, int> parse_size(const std::string& text) {
  const std::size_t x = text.find('x');
  int w = 0, h = 0;
  try {
    if (x != std::string::npos) {
      std::size_t used = 0;
      w = std::stoi(text.substr(0, x), &used);
      if (used != x) w = 0;
      h = std::stoi(text.substr(x + 1), &used);
      if (used != text.size() - x - 1) h = 0;
    }
  } catch (const std::exception&) {
    w = h = 0;
  }
  if (w < 16 || h < 16 || w > 8192 || h > 8192) {
    throw ParseError({"--size", std::nullopt, std::nullopt, "--size"},
                     fmt::format("'{}' is not WIDTHxHEIGHT in pixels (16 to 8192 each)", printable(text)));
  }
  return {w, h};
}

HeadlessOptions headless_options(const ViewOptions& o) {
  HeadlessOptions h;
  std::tie(h.width, h.height) = parse_size(o.size);
  return h;
}

// Writes the page to a temporary sibling of `beside` for Chromium, removed afterwards.
template <class Fn>
void with_page_file(const std::string& beside, const std::string& page, Fn fn) {
  // A name of its own beside the output, ending in .html (Chromium reads a
  // file by its extension).
  const fs::path tmp = temporary_sibling(beside).string() + ".html";
  write_text_file_atomically(tmp, page);
  try {
    fn(tmp.string());
  } catch (...) {
    std::error_code ec;
    fs::remove(tmp, ec);
    throw;
  }
  std::error_code ec;
  fs::remove(tmp, ec);
}

void measure(const ViewOptions& o, const std::vector<std::uint8_t>& glb, const ViewerPageOptions& page) {
  ViewerPageOptions bench = page;
  bench.bench = true;
  const fs::path dir = fs::temp_directory_path() / "rove-view-measure.html";
  with_page_file(dir.string(), standalone_page(glb, bench), [&](const std::string& html) {
    const Stopwatch watch;
    HeadlessOptions h = headless_options(o);
    h.virtual_time_ms = 120'000;
    const std::string stats = page_stats_json(headless_dump_dom(file_url(html), h));
    fmt::print("measured in headless Chromium ({}, {:.1f} s wall clock): {}\n", o.size, watch.elapsed(),
               stats.empty() ? "the page published no stats" : stats);
  });
}

void run_view(const ViewOptions& o) {
  std::vector<fs::path> outputs;
  for (const auto* out : {&o.glb, &o.html, &o.screenshot}) {
    if (!out->empty()) outputs.emplace_back(*out);
  }
  std::vector<fs::path> inputs(o.inputs.begin(), o.inputs.end());
  check_outputs_distinct(inputs, outputs);
  if (!o.screenshot.empty() && !fs::path(o.screenshot).has_extension()) {
    throw ParseError({"--screenshot", std::nullopt, std::nullopt, "--screenshot"}, "give a .png file name");
  }
  if (!o.screenshot.empty() || o.measure) parse_size(o.size);

  SceneLoadOptions lo;
  lo.cloud.max_points = o.max_points;
  Scene scene;
  const SceneLoadReport report = build_scene(scene, o.inputs, lo);
  for (const auto& l : report.loaded) fmt::print("{}\n", l);
  std::vector<Issue> issues;
  for (const auto& s : report.skipped) issues.push_back({"skipped-input", s});
  if (report.skipped_points > 0) {
    issues.push_back({"skipped-points", fmt::format("{} points with a coordinate that is not finite were left out",
                                                    report.skipped_points)});
  }
  if (scene.layers.empty()) {
    print_issues(issues);
    throw InvalidArgument(fmt::format("nothing to show: none of the {} inputs could be read", o.inputs.size()));
  }
  const std::vector<std::uint8_t> glb = write_glb_to_memory(scene);
  fmt::print("scene: {} layers, {} vertices, {:.1f} MB as glTF\n", scene.layers.size(), scene.vertex_count(),
             static_cast<double>(glb.size()) / 1e6);
  ViewerPageOptions page;
  page.three_dir = o.three_dir;
  page.lod_budget = o.lod_points;

  if (!o.glb.empty()) {
    write_text_file_atomically(o.glb, std::string_view(reinterpret_cast<const char*>(glb.data()), glb.size()));
    fmt::print("wrote {}\n", printable(o.glb));
  }
  if (!o.html.empty()) {
    write_text_file_atomically(o.html, standalone_page(glb, page));
    fmt::print("wrote {}\n", printable(o.html));
  }
  if (!o.screenshot.empty()) {
    ViewerPageOptions picture = page;
    picture.panel = false;
    with_page_file(o.screenshot, standalone_page(glb, picture), [&](const std::string& html) {
      headless_screenshot(file_url(html), o.screenshot, headless_options(o));
    });
    fmt::print("wrote {}\n", printable(o.screenshot));
  }
  if (o.measure) measure(o, glb, page);
  const bool serve = o.serve || (o.glb.empty() && o.html.empty() && o.screenshot.empty() && !o.measure);
  if (serve) {
    ViewerServerOptions so;
    so.host = o.host;
    so.port = o.port;
    so.page = page;
    ViewerServer server(glb, so);
    print_issues(issues);
    fmt::print("serving {} on {} (Ctrl-C stops)\n", scene.title, server.url());
    std::fflush(stdout);
    server.wait();
    return;
  }
  finish(issues);
}

}  // namespace

void add_view_command(CLI::App& app) {
  auto o = std::make_shared<ViewOptions>();
  auto* cmd = app.add_subcommand(
      "view",
      "Show rove's files and output folders as one 3D scene in a web browser: served on localhost (over SSH, "
      "forward the port: ssh -L 8080:localhost:8080 HOST), exported as glTF (--export), as one self-contained "
      "page (--html), or rendered to a PNG by headless Chromium (--screenshot). Reads .pcd .ply, map.yaml, .bt "
      ".ot, TUM/KITTI trajectories, .g2o/.graph pose graphs, rawlogs (scans along the odometry), pf-localization "
      "particle and step files, and the output folders of icp-slam, lidar-slam, pf-localization and nav run. "
      "Inputs that cannot be read are skipped and listed (exit status 3)");
  cmd->add_option("inputs", o->inputs, "Files and output folders to show together")->required();
  cmd->add_option("--port", o->port, "Port of the viewer (0: any free port)")->check(CLI::Range(0, 65535))
      ->capture_default_str();
  cmd->add_option("--host", o->host,
                  "Address to listen on; 127.0.0.1 serves this machine only, 0.0.0.0 every machine that can "
                  "reach it")
      ->capture_default_str();
  cmd->add_option("--export", o->glb, "Write the scene as glTF 2.0 binary (.glb) with rove's metadata");
  cmd->add_option("--html", o->html, "Write one self-contained page (three.js and the scene inlined)");
  cmd->add_option("--screenshot", o->screenshot,
                  "Render the page in headless Chromium (software WebGL) and write a PNG of it");
  cmd->add_option("--size", o->size, "Window of --screenshot and --measure, WIDTHxHEIGHT pixels")
      ->capture_default_str();
  cmd->add_option("--max-points", o->max_points,
                  "Points of a cloud kept at most (an even sample of larger clouds)")
      ->check(CLI::Range(std::size_t{1}, std::size_t{100'000'000}))
      ->capture_default_str();
  cmd->add_option("--lod-points", o->lod_points,
                  "Points of a large cloud drawn while the camera moves (all when it rests)")
      ->check(CLI::Range(std::size_t{1}, std::size_t{100'000'000}))
      ->capture_default_str();
  cmd->add_option("--three-dir", o->three_dir, "Folder of three.js (Debian's libjs-three)")->capture_default_str();
  cmd->add_flag("--serve", o->serve, "Serve the scene also when writing files");
  cmd->add_flag("--measure", o->measure,
                "Load the page in headless Chromium and print its load time and frames per second");
  cmd->callback([o] { run_view(*o); });
}

}  // namespace rove::cli
