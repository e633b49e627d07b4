// The kf-slam picture rasterized as palette indices and written by io's PNG
// writer.
#include "kf_slam_picture.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <vector>

#include <Eigen/Eigenvalues>

#include "canvas.h"
#include "rove/core/check.h"
#include "rove/io/gray_image.h"

namespace rove::cli {
namespace {

using Color = std::uint8_t;
constexpr Color kBackground = 0, kTruthPath = 1, kTruthLandmark = 2, kPath = 3, kEllipse = 4,
                kLandmark = 5, kSample = 6;
const std::vector<PaletteColor> kPalette = {
    {255, 255, 255},  // background
    {150, 150, 150},  // ground-truth path
    {0, 160, 0},      // ground-truth landmarks
    {40, 80, 220},    // estimated path
    {245, 160, 60},   // uncertainty ellipses
    {200, 0, 0},      // landmarks
    {150, 60, 200},   // samples
};

// Points of the x-y marginal ellipse of `cov` at `k` standard deviations.
std::vector<Eigen::Vector2d> ellipse(const Eigen::Vector2d& c, const Eigen::Matrix2d& cov,
                                     double k) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(cov);
  const Eigen::Vector2d sd = es.eigenvalues().cwiseMax(0.0).cwiseSqrt() * k;
  std::vector<Eigen::Vector2d> pts;
  constexpr int kSegments = 48;
  for (int i = 0; i <= kSegments; ++i) {
    const double a = 2.0 * std::numbers::pi * i / kSegments;
    pts.push_back(c + es.eigenvectors() * Eigen::Vector2d(sd[0] * std::cos(a), sd[1] * std::sin(a)));
  }
  return pts;
}

}  // namespace

void write_landmark_picture(const LandmarkPicture& pic, double quantiles, const std::string& path,
                            int size_px) {
  ROVE_CHECK_MSG(size_px >= 64 && size_px <= 8192, "picture size {} outside [64, 8192]", size_px);
  Eigen::Vector2d lo = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector2d hi = -lo;
  auto grow = [&](const std::vector<Eigen::Vector2d>& ps) {
    for (const auto& p : ps) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  };
  grow(pic.path);
  grow(pic.truth_path);
  grow(pic.true_landmarks);
  for (const auto& l : pic.landmarks) grow({l.mean});
  if (!(lo.x() <= hi.x())) lo.setConstant(-1.0), hi.setConstant(1.0);
  const int margin = 20;
  const double span = std::max({hi.x() - lo.x(), hi.y() - lo.y(), 1e-9});
  const double scale = (size_px - 2 * margin) / span;
  const Eigen::Vector2d mid = 0.5 * (lo + hi);
  Canvas canvas(size_px, size_px, kBackground);
  auto px = [&](const Eigen::Vector2d& p) {
    return Eigen::Vector2i(size_px / 2 + static_cast<int>(std::lround((p.x() - mid.x()) * scale)),
                           size_px / 2 - static_cast<int>(std::lround((p.y() - mid.y()) * scale)));
  };
  auto polyline = [&](const std::vector<Eigen::Vector2d>& pts, Color c) {
    for (std::size_t i = 1; i < pts.size(); ++i) {
      const Eigen::Vector2i a = px(pts[i - 1]), b = px(pts[i]);
      canvas.line(a.x(), a.y(), b.x(), b.y(), c);
    }
  };
  for (const auto& q : pic.samples) {
    const Eigen::Vector2i p = px(q);
    canvas.set(p.x(), p.y(), kSample);
  }
  polyline(pic.truth_path, kTruthPath);
  polyline(pic.path, kPath);
  for (const auto& t : pic.true_landmarks) {
    const Eigen::Vector2i p = px(t);
    canvas.line(p.x() - 4, p.y(), p.x() + 4, p.y(), kTruthLandmark);
    canvas.line(p.x(), p.y() - 4, p.x(), p.y() + 4, kTruthLandmark);
  }
  for (const auto& l : pic.landmarks) polyline(ellipse(l.mean, l.covariance, quantiles), kEllipse);
  for (const auto& l : pic.landmarks) {
    const Eigen::Vector2i p = px(l.mean);
    canvas.dot(p.x(), p.y(), 2, kLandmark);
  }
  PngEncoding encoding;
  encoding.palette = kPalette;
  write_png(path, canvas.image(), encoding);
}

void write_kf_slam_picture(const KfSlamResult& res, double quantiles, const std::string& path,
                           int size_px) {
  LandmarkPicture pic;
  for (const auto& s : res.steps) {
    pic.path.push_back(s.pose.translation().head<2>());
    if (s.ground_truth) pic.truth_path.push_back(s.ground_truth->translation().head<2>());
  }
  for (const auto& l : res.landmarks) {
    if (l.truth) pic.true_landmarks.push_back(l.truth->head<2>());
    pic.landmarks.push_back({l.mean.head<2>(), l.covariance.topLeftCorner<2, 2>()});
  }
  write_landmark_picture(pic, quantiles, path, size_px);
}

}  // namespace rove::cli
