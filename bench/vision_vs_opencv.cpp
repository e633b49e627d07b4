// rove::vision beside OpenCV's own calls on TUM fr1/rpy frame pairs
// (bench/vision.cmake): ORB extraction (OpenCV's in both), binary matching
// with a cross check, PnP with RANSAC. OpenCV runs on one thread.
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>
#include <opencv2/calib3d.hpp>
#include <opencv2/features2d.hpp>

#include "rove/vision/binary_matching.h"
#include "rove/vision/orb.h"
#include "rove/vision/pnp.h"
#include "rove/vision/rgbd_frame.h"

namespace {

using namespace rove;

PinholeCamera fr1_camera() {
  PinholeCamera c;  // TUM's default intrinsics of the registered depth
  c.width = 640;
  c.height = 480;
  c.fx = 517.306;
  c.fy = 516.469;
  c.cx = 318.643;
  c.cy = 255.314;
  return c;
}

struct PairData {
  Features a, b;
  std::vector<Eigen::Vector3d> points;  // a's 3D points of the matches
  std::vector<Eigen::Vector2d> pixels;  // b's pixels of the matches
};

struct Data {
  std::vector<RgbdFrame> frames;
  std::vector<PairData> pairs;
};

const Data& data() {
  static const Data d = [] {
    Data out;
    const std::string dir = std::string(ROVE_DATASETS_DIR) + "/rgbd/tum_fr1_rpy/";
    std::ifstream in(dir + "associations.txt");
    std::string line;
    for (int i = 0; std::getline(in, line) && out.frames.size() < 21; ++i) {
      if (i % 10 != 0) continue;  // 21 frames 1/3 s apart, 20 pairs
      std::istringstream s(line);
      std::string t0, rgb, t1, depth;
      s >> t0 >> rgb >> t1 >> depth;
      out.frames.push_back(read_rgbd_frame(dir + rgb, dir + depth, 5000.0));
    }
    const PinholeCamera c = fr1_camera();
    for (std::size_t i = 0; i + 1 < out.frames.size(); ++i) {
      PairData p;
      p.a = extract_orb(out.frames[i].color);
      p.b = extract_orb(out.frames[i + 1].color);
      for (const DescriptorMatch& m : match_binary(p.a.descriptors, p.b.descriptors)) {
        Eigen::Vector3d X;
        const Keypoint& ka = p.a.keypoints[m.query];
        if (!depth_point(out.frames[i].depth, c, ka.u, ka.v, 0.1, 8.0, X)) continue;
        p.points.push_back(X);
        p.pixels.emplace_back(p.b.keypoints[m.train].u, p.b.keypoints[m.train].v);
      }
      out.pairs.push_back(std::move(p));
    }
    return out;
  }();
  return d;
}

cv::Mat to_mat(const std::vector<OrbDescriptor>& d) {
  cv::Mat m(static_cast<int>(d.size()), 32, CV_8U);
  for (std::size_t i = 0; i < d.size(); ++i) std::memcpy(m.ptr(static_cast<int>(i)), d[i].data(), 32);
  return m;
}

void BM_OrbExtract(benchmark::State& state) {
  const Data& d = data();
  std::size_t i = 0, features = 0;
  for (auto _ : state) {
    const Features f = extract_orb(d.frames[i++ % d.frames.size()].color);
    features += f.keypoints.size();
    benchmark::DoNotOptimize(f);
  }
  state.counters["features"] = static_cast<double>(features) / static_cast<double>(state.iterations());
}
BENCHMARK(BM_OrbExtract)->Unit(benchmark::kMillisecond);

void BM_MatchCrossCheck_Rove(benchmark::State& state) {
  const Data& d = data();
  BinaryMatchOptions o;
  o.ratio = 0.0;
  o.max_distance = 256;
  std::size_t i = 0, n = 0;
  for (auto _ : state) {
    const PairData& p = d.pairs[i++ % d.pairs.size()];
    n += match_binary(p.a.descriptors, p.b.descriptors, o).size();
  }
  state.counters["matches"] = static_cast<double>(n) / static_cast<double>(state.iterations());
}
BENCHMARK(BM_MatchCrossCheck_Rove)->Unit(benchmark::kMillisecond);

void BM_MatchCrossCheck_OpenCv(benchmark::State& state) {
  const Data& d = data();
  std::vector<std::pair<cv::Mat, cv::Mat>> mats;
  for (const PairData& p : d.pairs) mats.emplace_back(to_mat(p.a.descriptors), to_mat(p.b.descriptors));
  cv::BFMatcher bf(cv::NORM_HAMMING, true);
  std::size_t i = 0, n = 0;
  for (auto _ : state) {
    const auto& [a, b] = mats[i++ % mats.size()];
    std::vector<cv::DMatch> m;
    bf.match(a, b, m);
    n += m.size();
  }
  state.counters["matches"] = static_cast<double>(n) / static_cast<double>(state.iterations());
}
BENCHMARK(BM_MatchCrossCheck_OpenCv)->Unit(benchmark::kMillisecond);

void BM_PnpRansac_Rove(benchmark::State& state) {
  const Data& d = data();
  const PinholeCamera c = fr1_camera();
  std::size_t i = 0, inliers = 0;
  for (auto _ : state) {
    const PairData& p = d.pairs[i++ % d.pairs.size()];
    inliers += solve_pnp_ransac(p.points, p.pixels, c).inliers.size();
  }
  state.counters["inliers"] = static_cast<double>(inliers) / static_cast<double>(state.iterations());
}
BENCHMARK(BM_PnpRansac_Rove)->Unit(benchmark::kMillisecond);

void BM_PnpRansac_OpenCv(benchmark::State& state) {
  const Data& d = data();
  const PinholeCamera c = fr1_camera();
  const cv::Matx33d K(c.fx, 0, c.cx, 0, c.fy, c.cy, 0, 0, 1);
  std::vector<std::pair<std::vector<cv::Point3d>, std::vector<cv::Point2d>>> sets;
  for (const PairData& p : d.pairs) {
    auto& s = sets.emplace_back();
    for (std::size_t k = 0; k < p.points.size(); ++k) {
      s.first.emplace_back(p.points[k].x(), p.points[k].y(), p.points[k].z());
      s.second.emplace_back(p.pixels[k].x(), p.pixels[k].y());
    }
  }
  std::size_t i = 0, inliers = 0;
  for (auto _ : state) {
    const auto& [obj, img] = sets[i++ % sets.size()];
    cv::Mat rvec, tvec;
    std::vector<int> in;
    // Same threshold (2 px), confidence (0.99) and sample cap (500) as rove's defaults.
    cv::solvePnPRansac(obj, img, K, cv::noArray(), rvec, tvec, false, 500, 2.0f, 0.99, in);
    inliers += in.size();
  }
  state.counters["inliers"] = static_cast<double>(inliers) / static_cast<double>(state.iterations());
}
BENCHMARK(BM_PnpRansac_OpenCv)->Unit(benchmark::kMillisecond);

}  // namespace

// One thread for OpenCV too, so both sides are timed on one core.
int main(int argc, char** argv) {
  cv::setNumThreads(1);
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
