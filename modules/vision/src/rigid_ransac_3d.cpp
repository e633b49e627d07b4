#include "rove/vision/rigid_ransac_3d.h"

#include <cmath>

#include <fmt/format.h>

#include "rove/core/check.h"
#include "rove/math/ransac.h"

namespace rove {
namespace {

struct PairDatum {
  Eigen::Vector3d target;
  Eigen::Vector3d source;
};

RigidFit3Result fit_pairs(std::span<const PairDatum> pairs, const RigidFitOptions& options) {
  std::vector<Eigen::Vector3d> t(pairs.size()), s(pairs.size());
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    t[i] = pairs[i].target;
    s[i] = pairs[i].source;
  }
  return fit_rigid_3d(t, s, {}, options);
}

struct RigidProblem {
  using Model = SE3d;
  using Datum = PairDatum;
  RigidFitOptions fit_options;

  std::size_t sample_size() const { return 3; }
  void fit(std::span<const Datum> sample, std::vector<Model>& models) const {
    const RigidFit3Result r = fit_pairs(sample, fit_options);
    if (r.termination == RegistrationTermination::Converged) models.push_back(r.T_target_source);
  }
  double distance(const Model& T, const Datum& d) const { return (T * d.source - d.target).norm(); }
  bool refit(std::span<const Datum> inliers, Model& T) const {
    const RigidFit3Result r = fit_pairs(inliers, fit_options);
    if (r.termination != RegistrationTermination::Converged) return false;
    T = r.T_target_source;
    return true;
  }
};

}  // namespace

void RigidRansac3dOptions::check() const {
  ROVE_CHECK_MSG(std::isfinite(inlier_distance) && inlier_distance > 0.0,
                 "RigidRansac3dOptions: inlier_distance = {} must be finite and > 0",
                 inlier_distance);
  ROVE_CHECK_MSG(success_probability > 0.0 && success_probability < 1.0,
                 "RigidRansac3dOptions: success_probability = {} must be in (0, 1)",
                 success_probability);
  ROVE_CHECK_GE(max_iterations, std::size_t{1});
  ROVE_CHECK_GE(min_inliers, std::size_t{3});
}

RigidRansac3dResult fit_rigid_3d_ransac(std::span<const Eigen::Vector3d> target,
                                        std::span<const Eigen::Vector3d> source,
                                        const RigidRansac3dOptions& options) {
  ROVE_CHECK_EQ(target.size(), source.size());
  options.check();
  RigidRansac3dResult result;
  std::vector<PairDatum> data(target.size());
  for (std::size_t i = 0; i < target.size(); ++i) {
    if (!target[i].allFinite() || !source[i].allFinite()) {
      result.message = fmt::format("pair {} has a non-finite coordinate", i);
      return result;
    }
    data[i] = {target[i], source[i]};
  }
  if (data.size() < options.min_inliers) {
    result.termination = RegistrationTermination::TooFewCorrespondences;
    result.message =
        fmt::format("{} pairs, fewer than min_inliers = {}", data.size(), options.min_inliers);
    return result;
  }
  RansacOptions ro;
  ro.distance_threshold = options.inlier_distance;
  ro.success_probability = options.success_probability;
  ro.max_iterations = options.max_iterations;
  ro.seed = options.seed;
  const auto r = ransac(RigidProblem{options.fit}, std::span<const PairDatum>(data), ro);
  result.ransac_iterations = r.iterations;
  if (!r.model) {
    result.termination = RegistrationTermination::Degenerate;
    result.message = fmt::format("no sample gave a rigid fit: {}", r.message);
    return result;
  }
  result.T_target_source = *r.model;
  result.inliers = r.inliers;
  if (result.inliers.size() < options.min_inliers) {
    result.termination = RegistrationTermination::TooFewCorrespondences;
    result.message = fmt::format("{} inliers of {} pairs, fewer than min_inliers = {}",
                                 result.inliers.size(), data.size(), options.min_inliers);
    return result;
  }
  std::vector<PairDatum> inlier_data;
  for (const std::size_t i : result.inliers) inlier_data.push_back(data[i]);
  const RigidFit3Result fit = fit_pairs(inlier_data, options.fit);
  result.termination = fit.termination;
  if (fit.termination != RegistrationTermination::Converged) {
    result.message = fmt::format("the fit on {} inliers failed: {}", inlier_data.size(), fit.message);
    return result;
  }
  result.T_target_source = fit.T_target_source;
  result.covariance = fit.covariance;
  result.rmse = fit.rmse;
  result.message = fmt::format("{} inliers of {} pairs, RMS {:.4f} m, {} samples",
                               result.inliers.size(), data.size(), result.rmse,
                               result.ransac_iterations);
  return result;
}

}  // namespace rove
