// EKF-SLAM against MRPT 2.5.8's CRangeBearingKFSLAM / CRangeBearingKFSLAM2D
// (libmrpt-slam) on MRPT's kf-slam configs and logs, one config after the
// other in one process: the filter time per step of each library (MRPT:
// processActionObservation; rove: EkfSlam's step inside run_kf_slam, log
// reading excluded in both), the landmarks mapped, and the errors against the
// configs' ground truth: path RMSE over the steps and landmark RMSE (each
// estimated landmark against the true landmark of its ID when the readings
// carry IDs, else against the nearest true landmark, for both libraries).
// Usage: bench_kf_slam_vs_mrpt CONFIG.ini...
#include <mrpt/config/CConfigFile.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/obs/CRawlog.h>
#include <mrpt/poses/CPose3D.h>
#include <mrpt/serialization/CArchive.h>
#include <mrpt/slam/CRangeBearingKFSLAM.h>
#include <mrpt/slam/CRangeBearingKFSLAM2D.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "rove/core/ini.h"
#include "rove/slam/kf_slam_run.h"

namespace {

struct Truth {
  std::map<long, Eigen::Vector3d> landmarks;
  std::vector<Eigen::Vector3d> path;
};

std::vector<std::vector<double>> rows(const std::string& path) {
  std::vector<std::vector<double>> out;
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '%' || line[0] == '#') continue;
    std::istringstream ls(line);
    std::vector<double> v;
    double x;
    while (ls >> x) v.push_back(x);
    if (!v.empty()) out.push_back(v);
  }
  return out;
}

Truth load_truth(const rove::KfSlamConfig& c) {
  Truth t;
  if (!c.ground_truth_file.empty()) {
    for (const auto& r : rows(c.resolve(c.ground_truth_file, "ground_truth_file"))) {
      t.landmarks[static_cast<long>(r[6])] = Eigen::Vector3d(r[0], r[1], r[2]);
    }
  }
  if (!c.ground_truth_file_robot.empty()) {
    for (const auto& r : rows(c.resolve(c.ground_truth_file_robot, "ground_truth_file_robot"))) {
      t.path.emplace_back(r[0], r[1], r.size() >= 6 ? r[2] : 0.0);
    }
  }
  return t;
}

double nearest(const Truth& t, const Eigen::Vector3d& p) {
  double best = std::numeric_limits<double>::infinity();
  for (const auto& [id, q] : t.landmarks) best = std::min(best, (q - p).norm());
  return best;
}

struct MrptRun {
  std::size_t steps = 0, landmarks = 0;
  double seconds = 0.0, path_rmse = NAN, landmark_rmse = NAN;
};

template <class Slam, class PosePdf, class Point>
MrptRun run_mrpt(const std::string& config, const std::string& rawlog, const Truth& truth,
                 bool by_id, int dim) {
  mrpt::config::CConfigFile ini(config);
  Slam slam;
  slam.loadOptions(ini);
  mrpt::io::CFileGZInputStream f(rawlog);
  auto ar = mrpt::serialization::archiveFrom(f);
  mrpt::obs::CActionCollection::Ptr action;
  mrpt::obs::CSensoryFrame::Ptr sf;
  size_t entry = 0;
  MrptRun r;
  double p2 = 0.0;
  std::size_t np = 0;
  std::vector<Eigen::Vector3d> path;
  PosePdf pose;
  std::vector<Point> lms;
  std::map<unsigned int, mrpt::maps::CLandmark::TLandmarkID> ids;
  mrpt::math::CVectorDouble x;
  mrpt::math::CMatrixDouble P;
  while (mrpt::obs::CRawlog::readActionObservationPair(ar, action, sf, entry)) {
    const auto t0 = std::chrono::steady_clock::now();
    slam.processActionObservation(action, sf);
    r.seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    slam.getCurrentRobotPose(pose);
    const mrpt::poses::CPose3D m(pose.mean);
    path.emplace_back(m.x(), m.y(), dim == 3 ? m.z() : 0.0);
    ++r.steps;
  }
  // MRPT reads (action, frame) pairs and passes over a frame before the
  // first action: its step k is the log's step k + (frames − pairs).
  const std::size_t offset = truth.path.size() > r.steps ? truth.path.size() - r.steps : 0;
  for (std::size_t k = 0; k < path.size() && k + offset < truth.path.size(); ++k) {
    p2 += (path[k] - truth.path[k + offset]).squaredNorm(), ++np;
  }
  slam.getCurrentState(pose, lms, ids, x, P);
  r.landmarks = lms.size();
  if (np) r.path_rmse = std::sqrt(p2 / static_cast<double>(np));
  double l2 = 0.0;
  std::size_t nl = 0;
  for (std::size_t i = 0; i < lms.size(); ++i) {
    Eigen::Vector3d p = Eigen::Vector3d::Zero();
    p.x() = lms[i].x, p.y() = lms[i].y;
    if constexpr (std::is_same_v<Point, mrpt::math::TPoint3D>) p.z() = lms[i].z;
    double e = NAN;
    if (by_id) {
      const auto it = truth.landmarks.find(static_cast<long>(ids[static_cast<unsigned>(i)]));
      if (it != truth.landmarks.end()) e = (it->second - p).norm();
    } else {
      e = nearest(truth, p);
    }
    if (std::isfinite(e)) l2 += e * e, ++nl;
  }
  if (nl) r.landmark_rmse = std::sqrt(l2 / static_cast<double>(nl));
  return r;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s CONFIG.ini...\n", argv[0]);
    return 2;
  }
  std::printf("%-36s %5s %9s %9s %8s %8s %7s %9s %9s %9s %9s\n", "config", "steps", "LMs mrpt",
              "LMs rove", "ms mrpt", "ms rove", "ratio", "path mrpt", "path rove", "LM mrpt",
              "LM rove");
  for (int a = 1; a < argc; ++a) {
    const std::string config = argv[a];
    const rove::KfSlamConfig c = rove::load_kf_slam_config(rove::IniFile::load(config));
    const std::string rawlog = c.resolve(c.rawlog_file, "rawlog_file");
    const Truth truth = load_truth(c);
    const rove::KfSlamResult rr = rove::run_kf_slam(c, rawlog);
    const bool by_id = rr.association.by_id > 0;
    MrptRun mr;
    try {
      mr =
          c.dim == 3 ? run_mrpt<mrpt::slam::CRangeBearingKFSLAM, mrpt::poses::CPose3DQuatPDFGaussian,
                              mrpt::math::TPoint3D>(config, rawlog, truth, by_id, 3)
                   : run_mrpt<mrpt::slam::CRangeBearingKFSLAM2D, mrpt::poses::CPosePDFGaussian,
                              mrpt::math::TPoint2D>(config, rawlog, truth, by_id, 2);
    } catch (const std::exception& e) {
      std::printf("%s: MRPT failed: %.200s\n", config.c_str(), e.what());
    }
    // rove's landmark RMSE the same way as MRPT's (by ID or nearest truth).
    double l2 = 0.0;
    std::size_t nl = 0;
    for (const auto& l : rr.landmarks) {
      const double e = by_id ? (l.error ? *l.error : NAN) : nearest(truth, l.mean);
      if (std::isfinite(e)) l2 += e * e, ++nl;
    }
    const double rove_ms = 1e3 * rr.filter_seconds / static_cast<double>(rr.steps.size());
    const double mrpt_ms = 1e3 * mr.seconds / static_cast<double>(mr.steps);
    std::printf("%-36s %5zu %9zu %9zu %8.3f %8.3f %6.1fx %9.4f %9.4f %9.4f %9.4f\n",
                std::filesystem::path(config).filename().c_str(), rr.steps.size(), mr.landmarks,
                rr.landmarks.size(), mrpt_ms, rove_ms, mrpt_ms / rove_ms, mr.path_rmse,
                rr.path_rmse.value_or(NAN), mr.landmark_rmse,
                nl ? std::sqrt(l2 / static_cast<double>(nl)) : NAN);
  }
  return 0;
}
