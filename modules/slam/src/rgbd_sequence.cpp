#include "rove/slam/rgbd_sequence.h"

#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <map>
#include <utility>

#include "rove/core/check.h"
#include "rove/core/error.h"
#include "rove/core/files.h"
#include "rove/core/interrupt.h"
#include "rove/io/any_rawlog.h"
#include "rove/io/camera_file.h"
#include "rove/obs/sensory_frame.h"
#include "rove/io/tum_trajectory.h"

namespace rove {
namespace {

namespace fs = std::filesystem;

constexpr std::uint64_t kMaxListBytes = 256ull << 20;
constexpr const char* kCameraFiles[] = {"camera.yaml", "camera.txt", "parameters.txt", "camera.ini"};

PinholeCamera make_camera(double fx, double fy, double cx, double cy, std::array<double, 5> d = {}) {
  PinholeCamera c;
  c.width = 640;
  c.height = 480;
  c.fx = fx;
  c.fy = fy;
  c.cx = cx;
  c.cy = cy;
  c.distortion = d;
  return c;
}

std::string lower(std::string s) {
  for (char& ch : s) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  return s;
}

// Splits a line into whitespace-separated fields.
std::vector<std::string_view> fields_of(std::string_view line) {
  std::vector<std::string_view> out;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t' || line[i] == '\r')) ++i;
    std::size_t j = i;
    while (j < line.size() && line[j] != ' ' && line[j] != '\t' && line[j] != '\r') ++j;
    if (j > i) out.push_back(line.substr(i, j - i));
    i = j;
  }
  return out;
}

double parse_number(std::string_view text, const std::string& file, std::size_t line,
                    std::string_view field) {
  double v = 0.0;
  const auto r = std::from_chars(text.data(), text.data() + text.size(), v);
  if (r.ec != std::errc() || r.ptr != text.data() + text.size() || !std::isfinite(v)) {
    throw ParseError({file, line, std::nullopt, std::string(field)},
                     fmt::format("'{}' is not a finite number", printable(text)));
  }
  return v;
}

// Calls f(line_number, fields) for every line that is not blank or a comment.
template <class F>
void for_each_list_line(const fs::path& path, F&& f) {
  const std::string text = read_input_file(path, kMaxListBytes, "RGB-D list file");
  std::size_t line_no = 0, start = 0;
  while (start <= text.size()) {
    std::size_t end = text.find('\n', start);
    if (end == std::string::npos) end = text.size();
    ++line_no;
    const auto fields = fields_of(std::string_view(text).substr(start, end - start));
    if (!fields.empty() && fields[0].front() != '#') f(line_no, fields);
    start = end + 1;
  }
}

struct TimedFile {
  double time = 0.0;
  std::string path;
};

std::vector<TimedFile> read_timed_list(const fs::path& folder, const char* name) {
  std::vector<TimedFile> out;
  const fs::path p = folder / name;
  for_each_list_line(p, [&](std::size_t line, const std::vector<std::string_view>& f) {
    if (f.size() != 2) {
      throw ParseError({p.string(), line, std::nullopt, ""},
                       fmt::format("expected 'timestamp file', found {} fields", f.size()));
    }
    out.push_back({parse_number(f[0], p.string(), line, "timestamp"), (folder / f[1]).string()});
  });
  return out;
}

std::vector<RgbdSequenceFrame> read_associations(const fs::path& folder) {
  std::vector<RgbdSequenceFrame> out;
  const fs::path p = folder / "associations.txt";
  for_each_list_line(p, [&](std::size_t line, const std::vector<std::string_view>& f) {
    if (f.size() < 4) {
      throw ParseError({p.string(), line, std::nullopt, ""},
                       fmt::format("expected 't_rgb rgb_file t_depth depth_file', found {} fields",
                                   f.size()));
    }
    RgbdSequenceFrame fr;
    fr.time = parse_number(f[0], p.string(), line, "rgb timestamp");
    fr.color_path = (folder / f[1]).string();
    fr.depth_time = parse_number(f[2], p.string(), line, "depth timestamp");
    fr.depth_path = (folder / f[3]).string();
    out.push_back(std::move(fr));
  });
  return out;
}

// One-to-one pairs, closest time differences first (TUM's associate.py).
std::vector<RgbdSequenceFrame> associate_lists(const std::vector<TimedFile>& rgb,
                                               const std::vector<TimedFile>& depth, double max_dt,
                                               std::size_t& unassociated) {
  std::vector<std::pair<double, std::pair<std::size_t, std::size_t>>> candidates;
  std::vector<std::size_t> order(depth.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](auto a, auto b) { return depth[a].time < depth[b].time; });
  for (std::size_t i = 0; i < rgb.size(); ++i) {
    auto it = std::lower_bound(order.begin(), order.end(), rgb[i].time - max_dt,
                               [&](std::size_t d, double t) { return depth[d].time < t; });
    for (; it != order.end() && depth[*it].time <= rgb[i].time + max_dt; ++it) {
      candidates.push_back({std::abs(depth[*it].time - rgb[i].time), {i, *it}});
    }
  }
  std::sort(candidates.begin(), candidates.end());
  std::vector<bool> rgb_used(rgb.size()), depth_used(depth.size());
  std::vector<RgbdSequenceFrame> out;
  for (const auto& [dt, pr] : candidates) {
    if (rgb_used[pr.first] || depth_used[pr.second]) continue;
    rgb_used[pr.first] = depth_used[pr.second] = true;
    out.push_back({rgb[pr.first].time, rgb[pr.first].path, depth[pr.second].path, depth[pr.second].time});
  }
  unassociated = rgb.size() - out.size();
  std::sort(out.begin(), out.end(), [](const auto& a, const auto& b) { return a.time < b.time; });
  return out;
}

// Numbered images of a folder: number → path (stems that are not whole numbers are skipped).
std::map<long long, std::string> numbered_images(const fs::path& dir) {
  std::map<long long, std::string> out;
  for (const auto& e : fs::directory_iterator(dir)) {
    if (!e.is_regular_file()) continue;
    const std::string stem = e.path().stem().string();
    long long n = 0;
    const auto r = std::from_chars(stem.data(), stem.data() + stem.size(), n);
    if (r.ec == std::errc() && r.ptr == stem.data() + stem.size()) out[n] = e.path().string();
  }
  return out;
}

std::vector<RgbdSequenceFrame> read_numbered(const fs::path& color_dir, const fs::path& depth_dir) {
  const auto color = numbered_images(color_dir), depth = numbered_images(depth_dir);
  std::vector<RgbdSequenceFrame> out;
  for (const auto& [n, path] : color) {
    const auto d = depth.find(n);
    if (d == depth.end()) {
      throw ParseError({path, std::nullopt, std::nullopt, ""},
                       fmt::format("color image {} has no depth image numbered {} in {}", n, n,
                                   printable(depth_dir.string())));
    }
    const double t = static_cast<double>(n);
    out.push_back({t, path, d->second, t});
  }
  return out;
}

std::vector<StampedPose3> read_pose_txt(const fs::path& p, const std::vector<RgbdSequenceFrame>& frames) {
  std::vector<StampedPose3> out;
  std::size_t k = 0;
  for_each_list_line(p, [&](std::size_t line, const std::vector<std::string_view>& f) {
    if (f.size() != 7) {
      throw ParseError({p.string(), line, std::nullopt, ""},
                       fmt::format("expected 'x y z qx qy qz qw', found {} fields", f.size()));
    }
    double v[7];
    for (int i = 0; i < 7; ++i) v[i] = parse_number(f[i], p.string(), line, "pose");
    const Eigen::Quaterniond q(v[6], v[3], v[4], v[5]);
    if (q.norm() < 1e-9) {
      throw ParseError({p.string(), line, std::nullopt, "q"}, "quaternion of norm 0");
    }
    // Line k is frame number k + 1 (the folders number frames from 1).
    const double t = k < frames.size() ? frames[k].time : static_cast<double>(k + 1);
    out.push_back({t, SE3d(q.normalized(), Eigen::Vector3d(v[0], v[1], v[2]))});
    ++k;
  });
  return out;
}

void set_camera_from_file(RgbdSequence& s, const std::string& path) {
  const CameraFile f = read_camera_file(path);
  s.camera = f.camera;
  if (f.depth_scale) s.depth_scale = *f.depth_scale;
  s.camera_source = path;
}

// Camera for a folder: option (name or file), a file in the folder, else by name.
void resolve_camera(RgbdSequence& s, const fs::path& folder, const RgbdSequenceOptions& o) {
  if (!o.camera.empty()) {
    if (const auto named = named_camera(o.camera)) {
      s.camera = named->camera;
      s.depth_scale = named->depth_scale;
      s.rolling_shutter_readout = named->rolling_shutter_readout;
      s.camera_source = o.camera;
    } else if (fs::exists(o.camera)) {
      set_camera_from_file(s, o.camera);
    } else {
      throw ParseError({o.camera, std::nullopt, std::nullopt, "camera"},
                       "neither a camera file nor a camera name (tum-fr1, tum-fr2, tum-fr3, tum, "
                       "icl-nuim, kinect)");
    }
    return;
  }
  for (const char* name : kCameraFiles) {
    if (fs::is_regular_file(folder / name)) return set_camera_from_file(s, (folder / name).string());
  }
  fs::path abs = fs::absolute(folder).lexically_normal();
  if (!abs.has_filename()) abs = abs.parent_path();
  const std::string name = lower(abs.filename().string());
  std::string preset;
  if (s.format == RgbdSequenceFormat::Tum) {
    preset = "tum";
    if (name.find("freiburg1") != std::string::npos || name.find("fr1") != std::string::npos) preset = "tum-fr1";
    if (name.find("freiburg2") != std::string::npos || name.find("fr2") != std::string::npos) preset = "tum-fr2";
    if (name.find("freiburg3") != std::string::npos || name.find("fr3") != std::string::npos) preset = "tum-fr3";
  } else if (name.find("icl") != std::string::npos) {
    preset = "icl-nuim";
  } else {
    throw ParseError({folder.string(), std::nullopt, std::nullopt, "camera"},
                     "a folder of numbered frames needs a camera: put camera.yaml, camera.txt, "
                     "parameters.txt or camera.ini in it, or give a camera file or name "
                     "(icl-nuim, kinect, tum-fr1, ...)");
  }
  const NamedCamera c = *named_camera(preset);
  s.camera = c.camera;
  s.depth_scale = c.depth_scale;
  s.rolling_shutter_readout = c.rolling_shutter_readout;
  s.camera_source = preset;
}

void check_frames_exist(const RgbdSequence& s) {
  for (const auto& f : s.frames) {
    for (const std::string* p : {&f.color_path, &f.depth_path}) {
      if (!fs::is_regular_file(*p)) throw IoError(*p, "listed image not found (or not a regular file)");
    }
  }
}

constexpr const char* kScanField = "CObservation3DRangeScan";

// A rawlog scan's problem, naming the file, the entry and the field.
[[noreturn]] void scan_error(const std::string& path, std::uint64_t entry, const std::string& field,
                             const std::string& problem) {
  throw ParseError({path, std::nullopt, std::nullopt, field}, fmt::format("entry {}: {}", entry, problem));
}

// The scan's intensity camera, its size taken from the image when it
// states none (rove/vision/range_image_frame.h's intensity_camera_of).
PinholeCamera scan_camera(const RangeImage3D& o) {
  PinholeCamera c = o.intensity_camera;
  if (c.width == 0 && c.height == 0) {
    c.width = o.intensity->width;
    c.height = o.intensity->height;
  }
  return c;
}

// Checks what the pipeline needs of a scan (rgbd_frame_from_range_image's
// preconditions).
void check_scan(const RangeImage3D& o, const std::string& path, std::uint64_t entry) {
  try {
    o.check();
  } catch (const InvalidArgument& e) {
    scan_error(path, entry, kScanField, std::string("the 3D range scan is inconsistent: ") + e.what());
  }
  if (o.depth.pixel_count() == 0) {
    scan_error(path, entry, std::string(kScanField) + ".rangeImage",
               "the 3D range scan has no range image (rgbd-slam needs depth and intensity images)");
  }
  if (!o.intensity || o.intensity->empty()) {
    scan_error(path, entry, std::string(kScanField) + ".intensityImage",
               "the 3D range scan has no intensity image (rgbd-slam needs depth and intensity images)");
  }
  const Image& im = *o.intensity;
  if (im.pixel_type != PixelType::U8 || (im.channels != 1 && im.channels != 3)) {
    scan_error(path, entry, std::string(kScanField) + ".intensityImage",
               fmt::format("the intensity image has {} channels of {}-byte samples; rgbd-slam needs 8-bit "
                           "gray or RGB",
                           im.channels, bytes_per_sample(im.pixel_type)));
  }
  const PinholeCamera c = scan_camera(o);
  if (c.width != im.width || c.height != im.height) {
    scan_error(path, entry, std::string(kScanField) + ".cameraParamsIntensity",
               fmt::format("the intensity image is {}x{} but its camera is {}x{}", im.width, im.height, c.width,
                           c.height));
  }
}

RgbdSequence read_rawlog_sequence(const std::string& path, const RgbdSequenceOptions& options) {
  if (!options.camera.empty() || options.depth_scale) {
    throw InvalidArgument(fmt::format("{}: a rawlog's 3D range scans carry their cameras and depth units; a "
                                      "camera or a depth scale applies to sequence folders only",
                                      path));
  }
  RgbdSequence s;
  s.folder = path;
  s.format = RgbdSequenceFormat::Rawlog;
  AnyRawlogReader reader(path);
  std::uint64_t entry = 0;
  std::vector<bool> timed;  // per frame: the scan has a time
  while (const auto e = reader.next()) {
    throw_if_interrupted();
    const auto scans = range_images_of(*e);
    for (std::size_t k = 0; k < scans.size(); ++k) {
      const RangeImage3D& o = *scans[k];
      if (s.frames.empty()) {
        check_scan(o, path, entry);
        s.sensor_label = o.sensor_label;
        s.camera = scan_camera(o);
        s.depth_scale = o.depth.scale;
        s.camera_source = fmt::format("rawlog ({} intensity camera)", o.sensor_label.empty() ? std::string("the scans'")
                                                                                             : "'" + o.sensor_label + "'");
      } else if (o.sensor_label != s.sensor_label) {
        ++s.other_sensor_scans;
        continue;
      } else {
        check_scan(o, path, entry);
        if (!(scan_camera(o) == s.camera)) {
          scan_error(path, entry, std::string(kScanField) + ".cameraParamsIntensity",
                     "the intensity camera differs from the first scan's (one camera per sequence)");
        }
      }
      RgbdSequenceFrame f;
      timed.push_back(o.timestamp.valid());
      if (timed.back()) f.time = o.timestamp.to_seconds();
      f.rawlog_entry = entry;
      f.rawlog_scan = k;
      s.frames.push_back(f);
    }
    ++entry;
  }
  if (s.frames.empty()) {
    throw ParseError({path, std::nullopt, std::nullopt, "observations"},
                     fmt::format("no 3D range scan (CObservation3DRangeScan) in its {} entries: rgbd-slam needs "
                                 "depth and intensity images",
                                 entry));
  }
  const auto n_timed = static_cast<std::size_t>(std::count(timed.begin(), timed.end(), true));
  for (std::size_t i = 0; i < s.frames.size(); ++i) {
    if (n_timed == 0) {
      s.frames[i].time = static_cast<double>(i);
    } else if (!timed[i]) {
      scan_error(path, s.frames[i].rawlog_entry, std::string(kScanField) + ".timestamp",
                 "the scan has no time while others have one");
    }
    s.frames[i].depth_time = s.frames[i].time;
  }
  for (std::size_t i = 1; i < s.frames.size(); ++i) {
    if (!(s.frames[i].time > s.frames[i - 1].time)) {
      scan_error(path, s.frames[i].rawlog_entry, std::string(kScanField) + ".timestamp",
                 fmt::format("time {:.6f} s is not after the previous scan's {:.6f} s", s.frames[i].time,
                             s.frames[i - 1].time));
    }
  }
  return s;
}

}  // namespace

std::vector<std::shared_ptr<const RangeImage3D>> range_images_of(const RawlogEntry& entry) {
  if (const auto* sf = std::get_if<std::shared_ptr<const SensoryFrame>>(&entry)) return (*sf)->find_all<RangeImage3D>();
  if (const auto* o = std::get_if<std::shared_ptr<const Observation>>(&entry)) {
    if (auto r = std::dynamic_pointer_cast<const RangeImage3D>(*o)) return {r};
  }
  return {};
}

std::string_view to_string(RgbdSequenceFormat format) {
  switch (format) {
    case RgbdSequenceFormat::Tum: return "tum";
    case RgbdSequenceFormat::NumberedFrames: return "numbered-frames";
    case RgbdSequenceFormat::Rawlog: return "rawlog";
  }
  return "?";
}

std::optional<NamedCamera> named_camera(std::string_view name) {
  if (name == "tum-fr1") {
    return NamedCamera{make_camera(517.306408, 516.469215, 318.643040, 255.313989,
                                   {0.262383, -0.953104, -0.005358, 0.002628, 1.163314}),
                       5000.0, 0.02};
  }
  if (name == "tum-fr2") {
    return NamedCamera{make_camera(520.908620, 521.007327, 325.141442, 249.701764,
                                   {0.231222, -0.784899, -0.003257, -0.000105, 0.917205}),
                       5000.0};
  }
  if (name == "tum-fr3") return NamedCamera{make_camera(535.4, 539.2, 320.1, 247.6), 5000.0};
  if (name == "tum") return NamedCamera{make_camera(525.0, 525.0, 319.5, 239.5), 5000.0};
  if (name == "icl-nuim") return NamedCamera{make_camera(481.2, -480.0, 319.5, 239.5), 5000.0};
  if (name == "kinect") return NamedCamera{make_camera(518.0, 519.0, 325.5, 253.5), 1000.0};
  return std::nullopt;
}

RgbdSequence read_rgbd_sequence(const std::string& folder, const RgbdSequenceOptions& options) {
  ROVE_CHECK_MSG(std::isfinite(options.max_time_difference) && options.max_time_difference > 0.0,
                 "max_time_difference must be finite and > 0, got {}", options.max_time_difference);
  if (options.depth_scale) {
    ROVE_CHECK_MSG(std::isfinite(*options.depth_scale) && *options.depth_scale > 0.0,
                   "depth_scale must be finite and > 0, got {}", *options.depth_scale);
  }
  const fs::path dir(folder);
  if (fs::is_regular_file(dir)) return read_rawlog_sequence(folder, options);
  if (!fs::is_directory(dir)) {
    throw IoError(folder, "not a folder or a rawlog (an RGB-D sequence is a folder, or a rawlog of 3D range scans)");
  }
  RgbdSequence s;
  s.folder = folder;
  if (fs::exists(dir / "associations.txt")) {
    s.frames = read_associations(dir);
  } else if (fs::exists(dir / "rgb.txt") && fs::exists(dir / "depth.txt")) {
    s.frames = associate_lists(read_timed_list(dir, "rgb.txt"), read_timed_list(dir, "depth.txt"),
                               options.max_time_difference, s.unassociated_color);
  } else if ((fs::is_directory(dir / "color") || fs::is_directory(dir / "rgb")) &&
             fs::is_directory(dir / "depth")) {
    s.format = RgbdSequenceFormat::NumberedFrames;
    s.frames = read_numbered(fs::is_directory(dir / "color") ? dir / "color" : dir / "rgb", dir / "depth");
  } else {
    throw ParseError({folder, std::nullopt, std::nullopt, ""},
                     "not an RGB-D sequence: expected associations.txt, rgb.txt and depth.txt "
                     "(TUM), or color/ (or rgb/) and depth/ folders of numbered images");
  }
  if (s.frames.empty()) {
    throw ParseError({folder, std::nullopt, std::nullopt, ""}, "the sequence lists no frame");
  }
  std::stable_sort(s.frames.begin(), s.frames.end(),
                   [](const auto& a, const auto& b) { return a.time < b.time; });
  check_frames_exist(s);
  resolve_camera(s, dir, options);
  if (options.depth_scale) s.depth_scale = *options.depth_scale;
  if (s.format == RgbdSequenceFormat::Tum && fs::is_regular_file(dir / "groundtruth.txt")) {
    s.reference_path = (dir / "groundtruth.txt").string();
    s.reference = read_tum_trajectory(s.reference_path);
  } else if (s.format == RgbdSequenceFormat::NumberedFrames && fs::is_regular_file(dir / "pose.txt")) {
    s.reference_path = (dir / "pose.txt").string();
    s.reference = read_pose_txt(dir / "pose.txt", s.frames);
  }
  return s;
}

}  // namespace rove
