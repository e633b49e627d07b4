#include "rove/slam/ro_slam.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "rove/core/check.h"
#include "rove/core/parallel.h"
#include "rove/poses/pose3.h"
#include "rbpf_common.h"

namespace rove {
namespace {

/// T_map_robot of a planar pose as the beacon map takes it.
Pose3 to_pose3(const SE2d& T) {
  return Pose3(T.translation().x(), T.translation().y(), 0.0, T.angle(), 0.0, 0.0);
}

/// No NaN range and a finite antenna position on every reading (an
/// infinite or non-positive range reads as "no return", MRPT's convention).
/// Returns the readings with a usable range.
std::size_t check_ranges(const BeaconRanges& ranges) {
  std::size_t usable = 0;
  for (std::size_t i = 0; i < ranges.readings.size(); ++i) {
    const BeaconRange& r = ranges.readings[i];
    ROVE_CHECK_MSG(!std::isnan(r.range), "reading {} (beacon {}) has a NaN range", i, r.beacon_id);
    ROVE_CHECK_MSG(r.position_on_robot.allFinite(),
                   "reading {} (beacon {}) has a non-finite antenna position", i, r.beacon_id);
    usable += std::isfinite(r.range) && r.range > 0.0f ? 1 : 0;
  }
  return usable;
}

// The odometry's Gaussian is floored at (1 µm)² and (1 µrad)² so that a
// zero covariance (a log without noise model) still gives a density.
const detail::Mat3 kPriorFloor = detail::diag_sq(detail::Vec3(1e-6, 1e-6, 1e-6));

}  // namespace

void RoSlamOptions::check() const {
  ROVE_CHECK_MSG(particles >= 1, "sampleSize must be >= 1, got {}", particles);
  ROVE_CHECK_MSG(beta >= 0.0 && beta <= 1.0, "BETA must be in [0, 1], got {}", beta);
  ROVE_CHECK_MSG(std::isfinite(pow_factor) && pow_factor > 0.0 && pow_factor <= 1.0,
                 "powFactor must be in (0, 1], got {}", pow_factor);
  ROVE_CHECK_MSG(static_cast<int>(resampling) <= 3, "unknown resamplingMethod {}",
                 static_cast<int>(resampling));
  ROVE_CHECK_MSG(std::isfinite(likelihood.range_std) && likelihood.range_std > 0.0,
                 "rangeStd must be > 0, got {}", likelihood.range_std);
  ROVE_CHECK_MSG(insertion.min_elevation_deg <= insertion.max_elevation_deg,
                 "minElevation_deg ({}) must not exceed maxElevation_deg ({})",
                 insertion.min_elevation_deg, insertion.max_elevation_deg);
  (void)resolve_thread_count(num_threads);
}

struct RoSlam::Impl {
  explicit Impl(int threads) : team(resolve_thread_count(threads)) {}
  ThreadTeam team;
};

RoSlam::RoSlam(RoSlamOptions options) : options_(std::move(options)) {
  options_.check();
  impl_ = std::make_unique<Impl>(options_.num_threads);
  const auto empty = std::make_shared<const BeaconMap>(options_.insertion, options_.likelihood);
  particles_.assign(options_.particles, RoSlamParticle{SE2d(), empty, nullptr});
  log_weights_.assign(options_.particles, -std::log(static_cast<double>(options_.particles)));
}

RoSlam::~RoSlam() = default;

std::size_t RoSlam::best() const {
  return static_cast<std::size_t>(std::max_element(log_weights_.begin(), log_weights_.end()) -
                                  log_weights_.begin());
}

std::size_t RoSlam::insert(const BeaconRanges& ranges, std::uint64_t step) {
  (void)check_ranges(ranges);
  for (auto& p : particles_) p.path = detail::make_node(p.pose, step, p.path);
  return insert_all(ranges, derive_seed(options_.seed, 0));
}

std::size_t RoSlam::insert_all(const BeaconRanges& ranges, std::uint64_t seed) {
  const std::vector<std::vector<std::size_t>> groups = detail::copy_groups(particles_);
  std::vector<std::shared_ptr<const BeaconMap>> maps(groups.size());
  parallel_for(groups.size(), impl_->team, [&](std::size_t g) {
    const std::size_t first = groups[g].front();
    auto map = std::make_shared<BeaconMap>(*particles_[first].map);
    map->reseed(derive_seed(seed, first));
    map->insert(ranges, to_pose3(particles_[first].pose));
    maps[g] = std::move(map);
  });
  for (std::size_t g = 0; g < groups.size(); ++g) {
    for (const std::size_t i : groups[g]) particles_[i].map = maps[g];
  }
  return groups.size();
}

RoSlamUpdateResult RoSlam::update(const OdometryIncrement& motion, const BeaconRanges& ranges,
                                  std::uint64_t step, bool insert_ranges) {
  RoSlamUpdateResult result;
  result.readings = check_ranges(ranges);
  const detail::Gaussian3 prior = detail::motion_prior(motion, kPriorFloor);
  ++updates_;
  const std::uint64_t seed = derive_seed(options_.seed, updates_);
  const std::size_t n = particles_.size();
  std::vector<SE2d> poses(n);
  std::vector<double> factors(n);
  // pfStandardProposal: a sample of the motion model, weighted by the
  // likelihood of the ranges in the particle's map.
  parallel_for(n, impl_->team, [&](std::size_t i) {
    Rng rng = Rng::stream(seed, i);
    poses[i] = detail::apply_increment(particles_[i].pose, prior.sample(rng));
    factors[i] = particles_[i].map->log_likelihood(ranges, to_pose3(poses[i]));
  });
  const detail::Reweighting w =
      detail::reweigh(particles_, log_weights_, poses, factors, step, options_.pow_factor);
  result.ess = w.ess;
  if (result.ess < options_.beta) {
    detail::resample(particles_, log_weights_, options_.resampling, seed);
    result.resampled = true;
  }
  if (insert_ranges) result.insertions = insert_all(ranges, seed);
  const BeaconMap& top = *particles_[best()].map;
  result.beacons = top.beacons().size();
  for (const Beacon& b : top.beacons()) result.unresolved += b.kind != BeaconPdfKind::Gaussian ? 1 : 0;
  return result;
}

}  // namespace rove
