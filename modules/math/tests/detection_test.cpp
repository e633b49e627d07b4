#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "rove/core/error.h"
#include "rove/math/line_detection.h"
#include "rove/math/plane_detection.h"

namespace rove {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

struct PlaneScene {
  std::vector<Eigen::Vector3d> points;
  std::vector<int> label;  // index of the true plane, −1 for outliers
  std::vector<Plane3> truth;
};

// 3 planes × 300 points (±2 m patches, isotropic Gaussian noise σ) and 300
// outliers uniform in the box [−3, 3]³, shuffled.
PlaneScene make_plane_scene(std::uint64_t seed, double sigma) {
  PlaneScene scene;
  const Eigen::Vector3d normals[3] = {Eigen::Vector3d(0, 0, 1),
                                      Eigen::Vector3d(1, 0.2, 0).normalized(),
                                      Eigen::Vector3d(0.1, 1, 0.3).normalized()};
  const double offsets[3] = {1.0, -1.5, 2.0};
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, sigma);
  std::uniform_real_distribution<double> patch(-2.0, 2.0);
  std::uniform_real_distribution<double> box(-3.0, 3.0);
  std::vector<std::pair<Eigen::Vector3d, int>> all;
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector3d& n = normals[k];
    const Eigen::Vector3d u = n.unitOrthogonal();
    const Eigen::Vector3d v = n.cross(u);
    scene.truth.push_back({n, offsets[k]});
    for (int i = 0; i < 300; ++i) {
      const Eigen::Vector3d p = -offsets[k] * n + patch(rng) * u + patch(rng) * v +
                                Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
      all.emplace_back(p, k);
    }
  }
  for (int i = 0; i < 300; ++i) all.emplace_back(Eigen::Vector3d(box(rng), box(rng), box(rng)), -1);
  std::shuffle(all.begin(), all.end(), rng);
  for (const auto& [p, l] : all) {
    scene.points.push_back(p);
    scene.label.push_back(l);
  }
  return scene;
}

// Angle (rad) between the normals and offset difference after aligning signs.
void compare_planes(const Plane3& est, const Plane3& truth, double& angle, double& offset_err) {
  const double sign = est.normal.dot(truth.normal) < 0 ? -1.0 : 1.0;
  angle = std::acos(std::min(1.0, sign * est.normal.dot(truth.normal)));
  offset_err = std::abs(sign * est.offset - truth.offset);
}

TEST(DetectPlanes, FindsThreePlanesAmongOutliers) {
  const PlaneScene scene = make_plane_scene(2024, 0.005);
  PlaneDetectionOptions o;
  o.ransac.distance_threshold = 0.015;
  o.min_inliers = 100;
  const PlaneDetectionResult r = detect_planes(scene.points, o);
  ASSERT_EQ(r.detections.size(), 3u) << r.message;
  EXPECT_EQ(r.termination, DetectionTermination::NoSupportedModel) << r.message;

  std::vector<bool> matched(3, false);
  std::size_t assigned = 0;
  for (const auto& det : r.detections) {
    // Match to the true plane with the closest normal.
    int best = -1;
    double best_angle = 10.0, best_offset = 0.0;
    for (int k = 0; k < 3; ++k) {
      double angle = 0, off = 0;
      compare_planes(det.model, scene.truth[k], angle, off);
      if (angle < best_angle) {
        best = k;
        best_angle = angle;
        best_offset = off;
      }
    }
    ASSERT_GE(best, 0);
    EXPECT_FALSE(matched[best]) << "two detections for plane " << best;
    matched[best] = true;
    EXPECT_LT(best_angle, 1.0 * kDeg) << "plane " << best;
    EXPECT_LT(best_offset, 0.01) << "plane " << best;
    EXPECT_NEAR(det.model.normal.norm(), 1.0, 1e-12);
    EXPECT_LE(det.model.offset, 0.0) << "canonical sign";

    std::size_t correct = 0;
    for (std::size_t i : det.inliers) correct += scene.label[i] == best;
    const double precision = static_cast<double>(correct) / det.inliers.size();
    const double recall = static_cast<double>(correct) / 300.0;
    EXPECT_GE(precision, 0.95) << "plane " << best;
    EXPECT_GE(recall, 0.95) << "plane " << best;
    EXPECT_LT(det.rms_distance, 0.01);
    assigned += det.inliers.size();
  }
  EXPECT_EQ(assigned + r.unassigned.size(), scene.points.size());
  // Every index appears exactly once across detections and unassigned.
  std::vector<int> seen(scene.points.size(), 0);
  for (const auto& det : r.detections)
    for (std::size_t i : det.inliers) ++seen[i];
  for (std::size_t i : r.unassigned) ++seen[i];
  for (int s : seen) EXPECT_EQ(s, 1);
}

TEST(DetectPlanes, DeterministicForASeed) {
  const PlaneScene scene = make_plane_scene(7, 0.005);
  PlaneDetectionOptions o;
  o.ransac.distance_threshold = 0.015;
  o.min_inliers = 100;
  o.ransac.seed = 99;
  const auto a = detect_planes(scene.points, o);
  const auto b = detect_planes(scene.points, o);
  ASSERT_EQ(a.detections.size(), b.detections.size());
  for (std::size_t k = 0; k < a.detections.size(); ++k) {
    EXPECT_EQ(a.detections[k].model.normal, b.detections[k].model.normal);
    EXPECT_EQ(a.detections[k].model.offset, b.detections[k].model.offset);
    EXPECT_EQ(a.detections[k].inliers, b.detections[k].inliers);
    EXPECT_EQ(a.detections[k].ransac_iterations, b.detections[k].ransac_iterations);
  }
  EXPECT_EQ(a.unassigned, b.unassigned);
}

TEST(DetectPlanes, StopsAtMaxModels) {
  const PlaneScene scene = make_plane_scene(3, 0.005);
  PlaneDetectionOptions o;
  o.ransac.distance_threshold = 0.015;
  o.min_inliers = 100;
  o.max_models = 2;
  const auto r = detect_planes(scene.points, o);
  EXPECT_EQ(r.detections.size(), 2u);
  EXPECT_EQ(r.termination, DetectionTermination::MaxModels) << r.message;
}

TEST(DetectPlanes, TooFewPointsAndDegenerateInput) {
  std::vector<Eigen::Vector3d> few = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  PlaneDetectionOptions o;
  o.min_inliers = 10;
  auto r = detect_planes(few, o);
  EXPECT_TRUE(r.detections.empty());
  EXPECT_EQ(r.termination, DetectionTermination::TooFewData) << r.message;
  EXPECT_EQ(r.unassigned.size(), 3u);

  std::vector<Eigen::Vector3d> line;
  for (int i = 0; i < 100; ++i) line.emplace_back(1.0 + i, 2.0 * i, -0.5 * i);
  o.ransac.max_iterations = 100;
  r = detect_planes(line, o);
  EXPECT_TRUE(r.detections.empty());
  EXPECT_EQ(r.termination, DetectionTermination::NoSupportedModel);
  EXPECT_NE(r.message.find("degenerate"), std::string::npos) << r.message;
}

TEST(DetectPlanes, NanPointIsRejectedByIndex) {
  PlaneScene scene = make_plane_scene(1, 0.005);
  scene.points[17].y() = std::numeric_limits<double>::quiet_NaN();
  try {
    detect_planes(scene.points);
    ADD_FAILURE() << "no exception";
  } catch (const InvalidArgument& e) {
    EXPECT_NE(std::string(e.what()).find("points[17]"), std::string::npos) << e.what();
  }
  scene.points[17].y() = 0.0;
  scene.points[5].x() = std::numeric_limits<double>::infinity();
  EXPECT_THROW(detect_planes(scene.points), InvalidArgument);
  EXPECT_THROW(fit_plane(scene.points), InvalidArgument);
}

TEST(DetectPlanes, RejectsInvalidOptions) {
  const PlaneScene scene = make_plane_scene(1, 0.005);
  PlaneDetectionOptions o;
  o.min_inliers = 2;  // below the minimal sample
  EXPECT_THROW(detect_planes(scene.points, o), InvalidArgument);
  o = {};
  o.max_models = 0;
  EXPECT_THROW(detect_planes(scene.points, o), InvalidArgument);
}

TEST(FitPlane, ExactPointsGiveTheExactPlaneInCanonicalSign) {
  const Eigen::Vector3d n = Eigen::Vector3d(0.3, -0.4, 0.5).normalized();
  const double d = 0.75;  // positive: canonical form flips it
  const Eigen::Vector3d u = n.unitOrthogonal(), v = n.cross(u);
  std::vector<Eigen::Vector3d> pts;
  for (int i = 0; i < 20; ++i) pts.push_back(-d * n + std::sin(i) * 3.0 * u + std::cos(3 * i) * v);
  const auto plane = fit_plane(pts);
  ASSERT_TRUE(plane.has_value());
  EXPECT_NEAR((plane->normal + n).norm(), 0.0, 1e-12);
  EXPECT_NEAR(plane->offset, -d, 1e-12);
  for (const auto& p : pts) EXPECT_NEAR(plane->signed_distance(p), 0.0, 1e-12);

  // Through the origin: the largest normal component is made positive.
  std::vector<Eigen::Vector3d> origin = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}};
  for (auto& p : origin) p = Eigen::Vector3d(p.x(), p.y(), 0.0);
  const auto flat = fit_plane(origin);
  ASSERT_TRUE(flat.has_value());
  EXPECT_NEAR((flat->normal - Eigen::Vector3d::UnitZ()).norm(), 0.0, 1e-12);
}

TEST(FitPlane, MinimizesTheSumOfSquaredDistances) {
  std::mt19937_64 rng(5);
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<Eigen::Vector3d> pts;
  for (int i = 0; i < 50; ++i) pts.emplace_back(3 * g(rng), 2 * g(rng), 0.2 * g(rng) + 5.0);
  const auto plane = fit_plane(pts);
  ASSERT_TRUE(plane.has_value());
  auto cost = [&](const Eigen::Vector3d& n, double d) {
    double c = 0;
    for (const auto& p : pts) c += std::pow(n.dot(p) + d, 2);
    return c;
  };
  const double best = cost(plane->normal, plane->offset);
  // Any perturbed plane (normal rotated, offset shifted) costs more.
  for (int t = 0; t < 200; ++t) {
    const Eigen::Vector3d n =
        (plane->normal + 0.05 * Eigen::Vector3d(g(rng), g(rng), g(rng))).normalized();
    const double d = plane->offset + 0.05 * g(rng);
    EXPECT_GE(cost(n, d), best);
  }
}

TEST(FitPlane, DegenerateSetsHaveNoPlane) {
  EXPECT_FALSE(fit_plane(std::vector<Eigen::Vector3d>{}).has_value());
  EXPECT_FALSE(fit_plane(std::vector<Eigen::Vector3d>{{0, 0, 0}, {1, 1, 1}}).has_value());
  std::vector<Eigen::Vector3d> collinear;
  for (int i = 0; i < 10; ++i) collinear.emplace_back(i, 2 * i, 3 * i);
  EXPECT_FALSE(fit_plane(collinear).has_value());
  const std::vector<Eigen::Vector3d> same(5, Eigen::Vector3d(1, 2, 3));
  EXPECT_FALSE(fit_plane(same).has_value());
}

struct LineScene {
  std::vector<Eigen::Vector2d> points;
  std::vector<int> label;
  std::vector<Line2> truth;
};

// 3 wall-like segments × 200 points (Gaussian noise σ) and 200 outliers
// uniform in [−5, 5]², shuffled. The segments do not cross, so the true
// inlier sets barely overlap and "≥ 95% correct" is a fair demand.
LineScene make_line_scene(std::uint64_t seed, double sigma) {
  LineScene scene;
  const Eigen::Vector2d ends[3][2] = {{{-3.5, -3.0}, {3.5, -3.0}},
                                      {{4.0, -2.5}, {4.0, 3.5}},
                                      {{-3.9, 1.4}, {0.9, 2.9}}};
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, sigma);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::uniform_real_distribution<double> box(-5.0, 5.0);
  std::vector<std::pair<Eigen::Vector2d, int>> all;
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector2d a = ends[k][0], b = ends[k][1];
    const Eigen::Vector2d t = (b - a).normalized();
    const Eigen::Vector2d n(-t.y(), t.x());
    scene.truth.push_back({n, -n.dot(a)});
    for (int i = 0; i < 200; ++i) {
      all.emplace_back(a + unit(rng) * (b - a) + Eigen::Vector2d(noise(rng), noise(rng)), k);
    }
  }
  for (int i = 0; i < 200; ++i) all.emplace_back(Eigen::Vector2d(box(rng), box(rng)), -1);
  std::shuffle(all.begin(), all.end(), rng);
  for (const auto& [p, l] : all) {
    scene.points.push_back(p);
    scene.label.push_back(l);
  }
  return scene;
}

TEST(DetectLines, FindsThreeLinesAmongOutliers) {
  const LineScene scene = make_line_scene(77, 0.005);
  LineDetectionOptions o;
  o.ransac.distance_threshold = 0.015;
  o.min_inliers = 60;
  const LineDetectionResult r = detect_lines(scene.points, o);
  ASSERT_EQ(r.detections.size(), 3u) << r.message;
  std::vector<bool> matched(3, false);
  for (const auto& det : r.detections) {
    int best = -1;
    double best_cos = -1.0;
    for (int k = 0; k < 3; ++k) {
      const double c = std::abs(det.model.normal.dot(scene.truth[k].normal));
      if (c > best_cos) {
        best_cos = c;
        best = k;
      }
    }
    EXPECT_FALSE(matched[best]);
    matched[best] = true;
    const double sign = det.model.normal.dot(scene.truth[best].normal) < 0 ? -1.0 : 1.0;
    EXPECT_LT(std::acos(std::min(1.0, best_cos)), 1.0 * kDeg);
    EXPECT_LT(std::abs(sign * det.model.offset - scene.truth[best].offset), 0.01);
    EXPECT_NEAR(det.model.direction().dot(det.model.normal), 0.0, 1e-15);
    std::size_t correct = 0;
    for (std::size_t i : det.inliers) correct += scene.label[i] == best;
    EXPECT_GE(static_cast<double>(correct) / det.inliers.size(), 0.95);
    EXPECT_GE(static_cast<double>(correct) / 200.0, 0.95);
  }
}

TEST(DetectLines, NanPointIsRejectedByIndex) {
  LineScene scene = make_line_scene(1, 0.01);
  scene.points[3].x() = std::numeric_limits<double>::quiet_NaN();
  try {
    detect_lines(scene.points);
    ADD_FAILURE() << "no exception";
  } catch (const InvalidArgument& e) {
    EXPECT_NE(std::string(e.what()).find("points[3]"), std::string::npos) << e.what();
  }
}

TEST(FitLine, ExactAndDegenerate) {
  // y = 2x + 1  ⇔  2x − y + 1 = 0; canonical d ≤ 0 gives n = (−2, 1)/√5.
  std::vector<Eigen::Vector2d> pts;
  for (int i = -3; i <= 4; ++i) pts.emplace_back(i, 2.0 * i + 1.0);
  const auto line = fit_line(pts);
  ASSERT_TRUE(line.has_value());
  EXPECT_NEAR((line->normal - Eigen::Vector2d(-2, 1) / std::sqrt(5.0)).norm(), 0.0, 1e-12);
  EXPECT_NEAR(line->offset, -1.0 / std::sqrt(5.0), 1e-12);
  EXPECT_FALSE(fit_line(std::vector<Eigen::Vector2d>{{1, 1}}).has_value());
  EXPECT_FALSE(fit_line(std::vector<Eigen::Vector2d>(4, Eigen::Vector2d(2, 3))).has_value());
}

TEST(DetectionTermination, Names) {
  EXPECT_EQ(to_string(DetectionTermination::MaxModels), "MaxModels");
  EXPECT_EQ(to_string(DetectionTermination::TooFewData), "TooFewData");
  EXPECT_EQ(to_string(DetectionTermination::NoSupportedModel), "NoSupportedModel");
}

}  // namespace
}  // namespace rove
