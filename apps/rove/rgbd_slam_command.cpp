// `rove rgbd-slam INPUT [--config rgbd.ini] [-o DIR] [--json]`: RGB-D SLAM
// (rove/slam/rgbd_slam.h) over a TUM RGB-D folder, an ICL-NUIM folder, a
// folder of numbered frames with a camera file, or a rawlog of 3D range scans. Built when rove::vision is.
#include <fmt/format.h>

#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "commands.h"
#include "report.h"
#include "rove/core/error.h"
#include "rove/core/files.h"
#include "rove/core/ini.h"
#include "rove/core/interrupt.h"
#include "rove/core/json.h"
#include "rove/core/parallel.h"
#include "rove/core/progress.h"
#include "rove/core/timer.h"
#include "rove/graph/graph_io.h"
#include "rove/io/octree_files.h"
#include "rove/io/ply.h"
#include "rove/io/tum_trajectory.h"
#include "rove/slam/rgbd_sequence.h"
#include "rove/slam/rgbd_slam.h"
#include "rove/slam/rgbd_slam_run.h"

namespace rove::cli {
namespace {

namespace fs = std::filesystem;

constexpr const char* kOutputs[] = {"trajectory.tum", "keyframes.tum", "loops.csv",
                                    "map.ply",        "graph.g2o",     "summary.json"};
// Written when octree_resolution > 0.
constexpr const char* kOctreeOutput = "map.bt";

struct RgbdSlamCliOptions {
  std::string input;
  std::string config;
  std::string preset;
  std::string camera;
  std::optional<double> depth_scale;
  std::string out_dir = "rgbd-slam-out";
  std::optional<std::size_t> max_frames;
  std::optional<int> threads;
  bool json = false;
  bool progress = true;
};

// Options: the preset, then the config's [rgbd-slam] section, or the keys
// outside any section (the tutorial's parameters.txt).
RgbdSlamOptions load_options(const RgbdSlamCliOptions& o) {
  RgbdSlamOptions opt = o.preset == "tutorial" ? RgbdSlamOptions::tutorial() : RgbdSlamOptions();
  if (o.config.empty()) return opt;
  check_regular_input(o.config, "rgbd-slam config file");
  const IniFile ini = IniFile::load(o.config);
  const std::string section = ini.has_section("rgbd-slam") ? "rgbd-slam" : "";
  IniFile merged = ini;
  if (!o.preset.empty() && !ini.has(section, "preset")) merged.set(section, "preset", o.preset);
  const ConfigSection s(merged, section);
  opt = RgbdSlamOptions::from_config(s);
  s.check_all_read();
  return opt;
}

RgbdSlamOptions load_all_options(const RgbdSlamCliOptions& o) {
  RgbdSlamOptions opt = load_options(o);
  if (o.threads) opt.octree_threads = resolve_thread_count(*o.threads, "--threads");
  return opt;
}

// The octree map's counts, for the summary and the report.
struct OctreeSummary {
  double resolution = 0.0;
  std::size_t nodes = 0, leaves = 0, occupied_leaves = 0;
  std::size_t memory_bytes = 0;
};

void write_keyframes_and_loops(const fs::path& dir, const RgbdSlam& slam, std::vector<std::string>& files) {
  std::vector<TimedPose3> kfs;
  for (const RgbdKeyframe& k : slam.keyframes()) kfs.push_back({Timestamp::from_seconds(k.time), k.T_world_camera});
  write_tum_trajectory((dir / "keyframes.tum").string(), kfs);
  files.push_back((dir / "keyframes.tum").string());
  std::string csv = "keyframe,candidate,keyframe_time,candidate_time,kind,matches,inliers,motion_norm,accepted\n";
  const auto key = slam.keyframes();
  for (const RgbdLoopCheck& l : slam.loop_checks()) {
    csv += fmt::format("{},{},{:.6f},{:.6f},{},{},{},{:.4f},{}\n", l.keyframe, l.candidate,
                       key[l.keyframe].time, key[l.candidate].time, to_string(l.kind), l.matches,
                       l.inliers, l.motion_norm, l.accepted ? 1 : 0);
  }
  write_text_file_atomically(dir / "loops.csv", csv);
  files.push_back((dir / "loops.csv").string());
}

std::vector<std::string> write_outputs(const fs::path& dir, RgbdSlam& slam,
                                       std::optional<OctreeSummary>& octree) {
  std::vector<std::string> files;
  std::vector<TimedPose3> traj;
  for (const StampedPose3& p : rgbd_trajectory(slam)) traj.push_back({Timestamp::from_seconds(p.time), p.pose});
  write_tum_trajectory((dir / "trajectory.tum").string(), traj);
  files.push_back((dir / "trajectory.tum").string());
  write_keyframes_and_loops(dir, slam, files);
  write_ply((dir / "map.ply").string(), slam.map_cloud());
  files.push_back((dir / "map.ply").string());
  write_graph(slam.graph(), (dir / "graph.g2o").string(), GraphFileFormat::G2o);
  files.push_back((dir / "graph.g2o").string());
  if (slam.options().octree_resolution > 0.0) {
    const OccupancyOctree tree = slam.map_octree();
    write_octree((dir / kOctreeOutput).string(), tree, OctreeFileFormat::Binary, OctreeBinaryContent::MaxLikelihood);
    files.push_back((dir / kOctreeOutput).string());
    OctreeSummary& t = octree.emplace();
    t.resolution = tree.resolution();
    t.nodes = tree.num_nodes();
    t.memory_bytes = tree.memory_usage();
    tree.for_each_leaf([&](const OctreeLeaf& l) {
      ++t.leaves;
      t.occupied_leaves += tree.is_occupied(l.log_odds) ? 1 : 0;
    });
  }
  return files;
}

void write_stats(JsonWriter& j, const RgbdSlamStats& st, const RgbdSlamRunResult& r) {
  j.key("frames").value(st.frames).key("tracked").value(st.tracked).key("lost").value(st.lost);
  j.key("no_features").value(st.no_features).key("keyframes").value(st.keyframes);
  j.key("guided_tracked").value(st.guided_tracked).key("brute_force_tracked").value(st.brute_force_tracked);
  j.key("recovered").value(st.recovered).key("weak_edges").value(st.weak_edges);
  j.key("loop_checks").value(st.loop_checks).key("loops_accepted").value(st.loops_accepted);
  j.key("optimizations").value(st.optimizations);
  j.key("icp_edges").value(st.icp_edges).key("icp_refused").value(st.icp_refused);
  // Null until a frame has been tracked by PnP (the first frame is not).
  j.key("tracking_rmse_px");
  if (st.guided_tracked + st.brute_force_tracked > 0) {
    j.value(st.tracking_rmse_px);
  } else {
    j.null();
  }
  const double fps = r.processing_seconds > 0 ? static_cast<double>(r.frames) / r.processing_seconds : 0.0;
  const double total = r.processing_seconds + r.read_seconds;
  j.key("frames_per_second").value(fps);
  j.key("frames_per_second_with_reading").value(total > 0 ? static_cast<double>(r.frames) / total : 0.0);
  j.key("seconds").begin_object();
  j.key("reading").value(r.read_seconds).key("processing").value(r.processing_seconds);
  j.key("features").value(st.features_seconds).key("matching").value(st.matching_seconds);
  j.key("pnp").value(st.pnp_seconds).key("loop_closure").value(st.loop_seconds);
  j.key("graph").value(st.graph_seconds).key("map").value(st.map_seconds);
  j.key("octree").value(st.octree_seconds).key("icp").value(st.icp_seconds);
  j.key("bundle_adjustment").value(st.ba_seconds);
  j.end_object();
}

std::string summary_json(const RgbdSlamCliOptions& o, const RgbdSequence& seq, const RgbdSlam& slam,
                         const RgbdSlamRunResult& r, const std::optional<OctreeSummary>& octree,
                         const std::vector<std::string>& files, const std::vector<Issue>& issues) {
  JsonWriter j;
  j.begin_object();
  j.key("input").value(o.input).key("format").value(std::string(to_string(seq.format)));
  j.key("config").value(o.config).key("preset").value(o.preset.empty() ? std::string("default") : o.preset);
  j.key("camera").value(seq.camera_source).key("depth_scale").value(seq.depth_scale);
  j.key("rolling_shutter_readout").value(slam.options().rolling_shutter_readout.value_or(0.0));
  if (seq.format == RgbdSequenceFormat::Rawlog) {
    j.key("sensor_label").value(seq.sensor_label).key("other_sensor_scans").value(seq.other_sensor_scans);
  }
  write_stats(j, slam.stats(), r);
  j.key("sequence_seconds").value(r.last_time - r.first_time);
  if (const auto& g = slam.last_optimization()) {
    j.key("last_optimization").begin_object();
    j.key("termination").value(std::string(to_string(g->termination))).key("message").value(g->message);
    j.key("initial_chi2").value(g->initial_chi2).key("final_chi2").value(g->final_chi2);
    j.key("edges").value(g->num_edges_used);
    j.key("chi2_per_edge").value(g->num_edges_used > 0 ? g->final_chi2 / static_cast<double>(g->num_edges_used) : 0.0);
    j.end_object();
  }
  j.key("bundle_adjustment");
  if (const auto& b = slam.bundle_adjustment()) {
    j.begin_object();
    j.key("termination").value(std::string(to_string(b->termination))).key("message").value(b->message);
    j.key("applied").value(b->improved()).key("iterations").value(b->iterations);
    j.key("points").value(slam.stats().ba_points).key("observations").value(slam.stats().ba_observations);
    j.key("outliers").value(b->outliers).key("conflicting_tracks").value(slam.stats().ba_conflicts);
    j.key("initial_cost").value(b->initial_cost).key("final_cost").value(b->final_cost);
    j.key("rmse_px").value(b->rmse_px);
    j.end_object();
  } else {
    j.null();
  }
  if (r.ate) {
    j.key("ate").begin_object();
    j.key("reference").value(seq.reference_path).key("alignment").value("se3");
    j.key("poses").value(r.ate->translation.count).key("rmse_m").value(r.ate->translation.rmse);
    j.key("mean_m").value(r.ate->translation.mean).key("median_m").value(r.ate->translation.median);
    j.key("max_m").value(r.ate->translation.max).key("rotation_rmse_rad").value(r.ate->rotation.rmse);
    j.end_object();
  }
  j.key("octree");
  if (octree) {
    j.begin_object().key("file").value(kOctreeOutput).key("resolution").value(octree->resolution);
    j.key("threads").value(slam.options().octree_threads == 0 ? resolve_thread_count(0) : slam.options().octree_threads);
    j.key("nodes").value(octree->nodes).key("leaves").value(octree->leaves);
    j.key("occupied_leaves").value(octree->occupied_leaves).key("memory_bytes").value(octree->memory_bytes);
    j.end_object();
  } else {
    j.null();
  }
  j.key("files").value(files);
  write_issues(j, issues);
  j.end_object();
  return j.str() + "\n";
}

void print_report(const RgbdSlamCliOptions& o, const RgbdSequence& seq, const RgbdSlam& slam,
                  const RgbdSlamRunResult& r, const std::optional<OctreeSummary>& octree,
                  const std::vector<std::string>& files) {
  const RgbdSlamStats& st = slam.stats();
  const double readout = slam.options().rolling_shutter_readout.value_or(0.0);
  fmt::print("rgbd-slam: {} frames of '{}' ({}, camera {}, {})\n", r.frames, printable(o.input),
             to_string(seq.format), printable(seq.camera_source),
             readout > 0.0 ? fmt::format("rolling shutter {:.1f} ms", 1000.0 * readout) : std::string("global shutter"));
  fmt::print("  tracking: {} tracked, {} lost, {} without features; {} keyframes; {}\n", st.tracked, st.lost,
             st.no_features, st.keyframes,
             st.guided_tracked + st.brute_force_tracked > 0
                 ? fmt::format("reprojection RMSE {:.3f} px", st.tracking_rmse_px)
                 : std::string("no frame tracked by PnP"));
  fmt::print("  loop closure: {} of {} checks accepted; {} optimizations\n", st.loops_accepted,
             st.loop_checks, st.optimizations);
  if (slam.options().icp_voxel > 0.0) {
    fmt::print("  geometric edges (GICP of keyframe clouds): {} added, {} refused, {:.3f} s\n", st.icp_edges,
               st.icp_refused, st.icp_seconds);
  } else {
    fmt::print("  geometric edges (GICP of keyframe clouds): off (icp_voxel = 0)\n");
  }
  if (const auto& b = slam.bundle_adjustment()) {
    fmt::print("  bundle adjustment: {} points, {} observations ({} outliers), image RMSE {:.2f} px, {}{}, "
               "{:.3f} s\n",
               st.ba_points, st.ba_observations, b->outliers, b->rmse_px, to_string(b->termination),
               b->improved() ? "" : " (not applied)", st.ba_seconds);
  } else {
    fmt::print("  bundle adjustment: off\n");
  }
  fmt::print("  time: {:.1f} frames/s processing ({:.1f} with image reading); features {:.3f} s, "
             "matching {:.3f} s, PnP {:.3f} s, loops {:.3f} s, graph {:.3f} s, map {:.3f} s, reading {:.3f} s\n",
             r.processing_seconds > 0 ? r.frames / r.processing_seconds : 0.0,
             r.processing_seconds + r.read_seconds > 0 ? r.frames / (r.processing_seconds + r.read_seconds) : 0.0,
             st.features_seconds, st.matching_seconds, st.pnp_seconds, st.loop_seconds, st.graph_seconds,
             st.map_seconds, r.read_seconds);
  if (octree) {
    fmt::print("  octree: {} m cells, {} nodes ({} leaves, {} occupied), built in {:.3f} s\n", octree->resolution,
               octree->nodes, octree->leaves, octree->occupied_leaves, st.octree_seconds);
  }
  if (r.ate) {
    fmt::print("  ATE (SE3-aligned, {} poses, {}): RMSE {:.4f} m, max {:.4f} m\n", r.ate->translation.count,
               printable(seq.reference_path), r.ate->translation.rmse, r.ate->translation.max);
  }
  fmt::print("  wrote {} files to {}/\n", files.size() + 1, printable(o.out_dir));
}

void run(const RgbdSlamCliOptions& o) {
  RgbdSequenceOptions so;
  so.camera = o.camera;
  so.depth_scale = o.depth_scale;
  const RgbdSequence seq = read_rgbd_sequence(o.input, so);
  const RgbdSlamOptions opt = load_all_options(o);
  const fs::path dir(o.out_dir);
  if (fs::exists(dir) && !fs::is_directory(dir)) {
    throw IoError(o.out_dir, "the output folder (-o) exists and is not a folder");
  }
  std::vector<fs::path> planned, inputs{fs::path(o.input)};
  for (const char* f : kOutputs) planned.push_back(dir / f);
  if (opt.octree_resolution > 0.0) planned.push_back(dir / kOctreeOutput);
  if (!o.config.empty()) inputs.emplace_back(o.config);
  check_outputs_distinct(inputs, planned);

  RgbdSlam slam(seq.camera, for_sequence(opt, seq));
  RgbdSlamRunOptions ro;
  ro.max_frames = o.max_frames;
  std::optional<Progress> progress;
  const std::size_t n = std::min(seq.frames.size(), o.max_frames.value_or(seq.frames.size()));
  if (o.progress) progress.emplace(n, "rgbd-slam " + printable(o.input), std::cerr);
  ro.on_frame = [&](const RgbdFrameUpdate&) {
    if (progress) progress->advance();
  };
  const RgbdSlamRunResult r = run_rgbd_slam(slam, seq, ro);
  if (progress) progress->finish();

  std::vector<Issue> issues;
  for (const auto& i : r.issues) issues.push_back({i.code, i.message});
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw IoError(o.out_dir, "cannot create the output folder: " + ec.message());
  std::optional<OctreeSummary> octree;
  std::vector<std::string> files = write_outputs(dir, slam, octree);
  files.push_back((dir / "summary.json").string());
  const std::string summary = summary_json(o, seq, slam, r, octree, files, issues);
  write_text_file_atomically(dir / "summary.json", summary);
  if (o.json) {
    fmt::print("{}", summary);
  } else {
    files.pop_back();
    print_report(o, seq, slam, r, octree, files);
  }
  finish(issues);
}

}  // namespace

void add_rgbd_slam_command(CLI::App& app) {
  auto o = std::make_shared<RgbdSlamCliOptions>();
  auto* cmd = app.add_subcommand(
      "rgbd-slam",
      "RGB-D SLAM (ORB features, PnP visual odometry, keyframes, loop closure, pose graph; cloud "
      "and octree maps) over a "
      "TUM RGB-D folder, an ICL-NUIM folder, numbered frames with a camera file, or a rawlog of 3D range scans "
      "(MRPT's CObservation3DRangeScan)");
  cmd->add_option("input", o->input,
                  "the sequence folder, or a rawlog (MRPT or rove) of 3D range scans with intensity images")
      ->required();
  cmd->add_option("--config", o->config,
                  "options: an INI file's [rgbd-slam] section, or a parameters.txt with the RGB-D "
                  "SLAM tutorial's keys (docs/rgbd-slam.md)");
  cmd->add_option("--preset", o->preset, "starting values: default or tutorial")
      ->check(CLI::IsMember({"default", "tutorial"}));
  cmd->add_option("--camera", o->camera,
                  "camera file, or tum-fr1|tum-fr2|tum-fr3|tum|icl-nuim|kinect (default: from the "
                  "folder; a rawlog's scans carry their cameras)");
  cmd->add_option("--depth-scale", o->depth_scale, "depth image units per meter (default: the camera's)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("-o,--output", o->out_dir, "output folder")->capture_default_str();
  cmd->add_option("--max-frames", o->max_frames, "process at most this many frames (default: all)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--threads", o->threads,
                  fmt::format("threads inserting the keyframes' clouds into the octree map (map.bt), 1 to {}, 0 "
                              "for all hardware threads; the map does not depend on it (default: the config's "
                              "octree_threads, 1)",
                              kMaxThreads));
  cmd->add_flag("--json", o->json, "print the summary as JSON");
  cmd->add_flag("!--no-progress", o->progress, "do not report progress on stderr");
  cmd->callback([o] { run(*o); });
}

}  // namespace rove::cli
