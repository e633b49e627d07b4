#include "rove/poses/pdf_particles.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "rove/core/check.h"
#include "pdf_weights_detail.h"
#include "rove/math/statistics.h"

namespace rove {

template <PdfPose Pose>
PoseParticles<Pose>::PoseParticles(std::vector<Particle> particles)
    : particles_(std::move(particles)) {
  for (const Particle& p : particles_) detail::check_log_weight(p.log_weight);
}

template <PdfPose Pose>
PoseParticles<Pose>::PoseParticles(std::size_t n, const Pose& pose)
    : particles_(n, Particle{pose, 0.0}) {}

template <PdfPose Pose>
void PoseParticles<Pose>::push_back(const Pose& pose, double log_weight) {
  detail::check_log_weight(log_weight);
  particles_.push_back(Particle{pose, log_weight});
}

template <PdfPose Pose>
std::vector<double> PoseParticles<Pose>::normalized_weights() const {
  std::vector<double> lw;
  lw.reserve(particles_.size());
  for (const Particle& p : particles_) lw.push_back(p.log_weight);
  return weights_from_log_weights(lw);
}

template <PdfPose Pose>
void PoseParticles<Pose>::normalize_weights() {
  std::vector<double> lw;
  lw.reserve(particles_.size());
  for (const Particle& p : particles_) lw.push_back(p.log_weight);
  normalize_log_weights(lw);
  for (std::size_t i = 0; i < particles_.size(); ++i) particles_[i].log_weight = lw[i];
}

template <PdfPose Pose>
double PoseParticles<Pose>::effective_sample_size() const {
  double sum_sq = 0.0;
  for (double w : normalized_weights()) sum_sq += w * w;
  return 1.0 / sum_sq;
}

template <PdfPose Pose>
Pose PoseParticles<Pose>::mean() const {
  std::vector<Pose> poses;
  poses.reserve(particles_.size());
  for (const Particle& p : particles_) poses.push_back(p.pose);
  const std::vector<double> w = normalized_weights();
  return weighted_mean(std::span<const Pose>(poses), std::span<const double>(w));
}

template <PdfPose Pose>
typename PoseParticles<Pose>::Matrix PoseParticles<Pose>::covariance() const {
  const Pose m = mean();
  const std::vector<double> w = normalized_weights();
  Matrix C = Matrix::Zero();
  for (std::size_t i = 0; i < particles_.size(); ++i) {
    const Eigen::Matrix<double, kDim, 1> d = pose_difference(particles_[i].pose, m);
    C += w[i] * d * d.transpose();
  }
  return 0.5 * (C + C.transpose());
}

template <PdfPose Pose>
const typename PoseParticles<Pose>::Particle& PoseParticles<Pose>::most_likely() const {
  ROVE_CHECK_MSG(!particles_.empty(), "most_likely() of an empty particle set");
  return *std::max_element(particles_.begin(), particles_.end(),
                           [](const Particle& a, const Particle& b) {
                             return a.log_weight < b.log_weight;
                           });
}

template <PdfPose Pose>
Pose PoseParticles<Pose>::sample(std::mt19937_64& rng) const {
  const std::vector<double> w = normalized_weights();
  return particles_[detail::draw_index(w, rng)].pose;
}

template class PoseParticles<Pose2>;
template class PoseParticles<Pose3>;

}  // namespace rove
