#include "rove/io/camera_file.h"

#include <charconv>
#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "rove/core/error.h"
#include "rove/core/files.h"

namespace rove {
namespace {

struct Entry {
  std::string section;
  std::string key;
  std::string value;
  std::size_t line = 0;
};

std::string_view trim(std::string_view s) {
  const auto first = s.find_first_not_of(" \t\r");
  if (first == std::string_view::npos) return {};
  const auto last = s.find_last_not_of(" \t\r");
  return s.substr(first, last - first + 1);
}

// Every `key = value`, `key: value` or `key=value;` line, with its section.
std::vector<Entry> split_entries(std::string_view text) {
  std::vector<Entry> entries;
  std::string section;
  std::size_t line_no = 0;
  std::size_t pos = 0;
  while (pos <= text.size()) {
    const std::size_t end = std::min(text.find('\n', pos), text.size());
    std::string_view line = text.substr(pos, end - pos);
    pos = end + 1;
    ++line_no;
    if (const auto c = line.find_first_of("#;"); c != std::string_view::npos) line = line.substr(0, c);
    line = trim(line);
    if (line.empty() || line.starts_with("//") || line.starts_with('%') || line == "---") continue;
    if (line.front() == '[' && line.back() == ']') {
      section = std::string(trim(line.substr(1, line.size() - 2)));
      continue;
    }
    const auto sep = line.find_first_of("=:");
    if (sep == std::string_view::npos) continue;
    entries.push_back({section, std::string(trim(line.substr(0, sep))),
                       std::string(trim(line.substr(sep + 1))), line_no});
  }
  return entries;
}

class Reader {
 public:
  Reader(std::vector<Entry> entries, std::string_view source)
      : entries_(std::move(entries)), source_(source) {}

  const Entry* find(std::string_view key, const std::string* section = nullptr) const {
    for (const Entry& e : entries_) {
      if (e.key == key && (section == nullptr || e.section == *section)) return &e;
    }
    return nullptr;
  }

  [[noreturn]] void fail(const Entry* e, std::string_view key, const std::string& problem) const {
    throw ParseError({std::string(source_), e ? std::optional<std::size_t>(e->line) : std::nullopt,
                      std::nullopt, std::string(key)},
                     problem);
  }

  double number(const Entry& e) const {
    const std::string_view v = e.value;
    double x = 0.0;
    const auto [ptr, ec] = std::from_chars(v.data(), v.data() + v.size(), x);
    if (ec != std::errc() || ptr != v.data() + v.size() || !std::isfinite(x)) {
      fail(&e, e.key, fmt::format("'{}' is not a finite number", printable(v)));
    }
    return x;
  }

  std::vector<double> numbers(const Entry& e) const {
    std::string_view v = trim(e.value);
    if (v.starts_with('[') && v.ends_with(']')) v = v.substr(1, v.size() - 2);
    std::vector<double> out;
    std::size_t i = 0;
    while (i < v.size()) {
      while (i < v.size() && (v[i] == ' ' || v[i] == ',' || v[i] == '\t')) ++i;
      if (i == v.size()) break;
      double x = 0.0;
      const auto [ptr, ec] = std::from_chars(v.data() + i, v.data() + v.size(), x);
      if (ec != std::errc() || !std::isfinite(x)) {
        fail(&e, e.key, fmt::format("'{}' is not a list of finite numbers", printable(e.value)));
      }
      out.push_back(x);
      i = static_cast<std::size_t>(ptr - v.data());
    }
    return out;
  }

  double required(std::string_view key, const std::string* section = nullptr) const {
    const Entry* e = find(key, section);
    if (e == nullptr) fail(nullptr, key, fmt::format("the camera file has no '{}'", key));
    return number(*e);
  }

  std::optional<double> optional(std::string_view key, const std::string* section = nullptr) const {
    const Entry* e = find(key, section);
    if (e == nullptr) return std::nullopt;
    return number(*e);
  }

  std::uint32_t dimension(std::string_view key, double value, const Entry* e) const {
    if (!(value >= 1.0 && value <= 65536.0) || value != std::floor(value)) {
      fail(e, key, fmt::format("image size {} is not a whole number in [1, 65536]", value));
    }
    return static_cast<std::uint32_t>(value);
  }

 private:
  std::vector<Entry> entries_;
  std::string_view source_;
};

CameraFile read_tutorial(const Reader& r) {
  CameraFile f;
  f.format = CameraFileFormat::TutorialParameters;
  f.camera.fx = r.required("camera.fx");
  f.camera.fy = r.required("camera.fy");
  f.camera.cx = r.required("camera.cx");
  f.camera.cy = r.required("camera.cy");
  f.depth_scale = r.optional("camera.scale");
  return f;
}

CameraFile read_orbslam(const Reader& r, const std::string& prefix) {
  CameraFile f;
  f.format = CameraFileFormat::OrbSlamYaml;
  f.camera.fx = r.required(prefix + "fx");
  f.camera.fy = r.required(prefix + "fy");
  f.camera.cx = r.required(prefix + "cx");
  f.camera.cy = r.required(prefix + "cy");
  const char* names[5] = {"k1", "k2", "p1", "p2", "k3"};
  for (int i = 0; i < 5; ++i) {
    f.camera.distortion[static_cast<std::size_t>(i)] = r.optional(prefix + names[i]).value_or(0.0);
  }
  const std::string w = prefix + "width", h = prefix + "height";
  if (const auto v = r.optional(w)) f.camera.width = r.dimension(w, *v, r.find(w));
  if (const auto v = r.optional(h)) f.camera.height = r.dimension(h, *v, r.find(h));
  f.depth_scale = r.optional("DepthMapFactor");
  return f;
}

CameraFile read_mrpt(const Reader& r, const std::string& section) {
  CameraFile f;
  f.format = CameraFileFormat::MrptConfig;
  f.camera.fx = r.required("fx", &section);
  f.camera.fy = r.required("fy", &section);
  f.camera.cx = r.required("cx", &section);
  f.camera.cy = r.required("cy", &section);
  if (const Entry* e = r.find("dist", &section)) {
    const std::vector<double> d = r.numbers(*e);
    if (d.size() != 4 && d.size() != 5) {
      r.fail(e, "dist", fmt::format("expected 4 or 5 coefficients [k1 k2 p1 p2 (k3)], got {}",
                                    d.size()));
    }
    for (std::size_t i = 0; i < d.size(); ++i) f.camera.distortion[i] = d[i];
  }
  if (const Entry* e = r.find("resolution", &section)) {
    const std::vector<double> wh = r.numbers(*e);
    if (wh.size() != 2) r.fail(e, "resolution", "expected [width height]");
    f.camera.width = r.dimension("resolution", wh[0], e);
    f.camera.height = r.dimension("resolution", wh[1], e);
  }
  return f;
}

}  // namespace

std::string_view to_string(CameraFileFormat format) {
  switch (format) {
    case CameraFileFormat::TutorialParameters: return "parameters.txt";
    case CameraFileFormat::OrbSlamYaml: return "ORB-SLAM YAML";
    case CameraFileFormat::MrptConfig: return "MRPT camera config";
  }
  return "unknown";
}

CameraFile parse_camera_file(std::string_view text, std::string_view source) {
  const Reader r(split_entries(text), source);
  CameraFile f;
  if (r.find("camera.fx") != nullptr) {
    f = read_tutorial(r);
  } else if (r.find("Camera.fx") != nullptr) {
    f = read_orbslam(r, "Camera.");
  } else if (r.find("Camera1.fx") != nullptr) {
    f = read_orbslam(r, "Camera1.");
  } else if (const Entry* e = r.find("fx")) {
    f = read_mrpt(r, e->section);
  } else {
    r.fail(nullptr, "fx",
           "not a camera file: no 'camera.fx=' (parameters.txt), 'Camera.fx:' (ORB-SLAM YAML) "
           "or 'fx =' (MRPT camera config) key");
  }
  const auto bad = [&](std::string_view key, std::string_view what) {
    r.fail(r.find(key), key, std::string(what));
  };
  if (f.camera.fx == 0.0) bad("fx", "focal length fx is zero");
  if (f.camera.fy == 0.0) bad("fy", "focal length fy is zero");
  if (f.depth_scale && !(*f.depth_scale > 0.0)) {
    r.fail(nullptr, "depth scale", fmt::format("depth scale {} must be > 0", *f.depth_scale));
  }
  return f;
}

CameraFile read_camera_file(const std::string& path) {
  const std::string text = read_input_file(path, 1u << 20, "camera file");
  return parse_camera_file(text, path);
}

}  // namespace rove
