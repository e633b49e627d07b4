#include "rove/poses/pdf_sog.h"

#include <algorithm>

#include "rove/core/check.h"
#include "pdf_weights_detail.h"
#include "rove/math/statistics.h"

namespace rove {

template <PdfPose Pose>
PoseSOG<Pose>::PoseSOG(std::vector<Mode> modes) : modes_(std::move(modes)) {
  for (const Mode& m : modes_) detail::check_log_weight(m.log_weight);
}

template <PdfPose Pose>
void PoseSOG<Pose>::push_back(const Gaussian& gaussian, double log_weight) {
  detail::check_log_weight(log_weight);
  modes_.push_back(Mode{gaussian, log_weight});
}

template <PdfPose Pose>
std::vector<double> PoseSOG<Pose>::normalized_weights() const {
  std::vector<double> lw;
  lw.reserve(modes_.size());
  for (const Mode& m : modes_) lw.push_back(m.log_weight);
  return weights_from_log_weights(lw);
}

template <PdfPose Pose>
void PoseSOG<Pose>::normalize_weights() {
  std::vector<double> lw;
  lw.reserve(modes_.size());
  for (const Mode& m : modes_) lw.push_back(m.log_weight);
  normalize_log_weights(lw);
  for (std::size_t i = 0; i < modes_.size(); ++i) modes_[i].log_weight = lw[i];
}

template <PdfPose Pose>
Pose PoseSOG<Pose>::mean() const {
  std::vector<Pose> means;
  means.reserve(modes_.size());
  for (const Mode& m : modes_) means.push_back(m.gaussian.mean());
  const std::vector<double> w = normalized_weights();
  return weighted_mean(std::span<const Pose>(means), std::span<const double>(w));
}

template <PdfPose Pose>
typename PoseSOG<Pose>::Matrix PoseSOG<Pose>::covariance() const {
  // Law of total covariance: E[Cov(x | mode)] + Cov(E[x | mode]).
  const Pose m = mean();
  const std::vector<double> w = normalized_weights();
  Matrix C = Matrix::Zero();
  for (std::size_t i = 0; i < modes_.size(); ++i) {
    const auto d = pose_difference(modes_[i].gaussian.mean(), m);
    C += w[i] * (modes_[i].gaussian.covariance() + d * d.transpose());
  }
  return 0.5 * (C + C.transpose());
}

template <PdfPose Pose>
const typename PoseSOG<Pose>::Mode& PoseSOG<Pose>::most_likely() const {
  ROVE_CHECK_MSG(!modes_.empty(), "most_likely() of an empty sum of Gaussians");
  return *std::max_element(modes_.begin(), modes_.end(), [](const Mode& a, const Mode& b) {
    return a.log_weight < b.log_weight;
  });
}

template <PdfPose Pose>
Pose PoseSOG<Pose>::sample(std::mt19937_64& rng) const {
  const std::vector<double> w = normalized_weights();
  return modes_[detail::draw_index(w, rng)].gaussian.sample(rng);
}

template class PoseSOG<Pose2>;
template class PoseSOG<Pose3>;

}  // namespace rove
