#include "rove/slam/ekf_slam.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include <Eigen/Cholesky>
#include <fmt/format.h>

#include "rove/bayes/distributions.h"
#include "rove/core/check.h"
#include "rove/core/memory_budget.h"
#include "rove/poses/angle.h"
#include "ekf_slam_models.h"

namespace rove {

template <int Dim>
struct EkfSlam<Dim>::Linearization {
  Eigen::Matrix<double, kM, 1> z;    // predicted reading
  Eigen::Matrix<double, kM, kD> Hr;  // d z / d δ
  Eigen::Matrix<double, kM, kL> Hl;  // d z / d p_world
  Eigen::Index col = 0;              // the landmark's first state column
};

template <int Dim>
EkfSlam<Dim>::EkfSlam(EkfSlamOptions options) : options_(std::move(options)) {
  options_.check(Dim);
  ic_chi2_ = chi_square_quantile(options_.data_association.chi2_probability, kM);
  reserve(kD + 16 * kL);
  P_.topLeftCorner(kD, kD).setZero();
}

template <int Dim>
void EkfSlam<Dim>::reserve(Eigen::Index n) {
  if (n <= P_.rows()) return;
  const Eigen::Index cap = std::max<Eigen::Index>(n, 2 * P_.rows());
  check_memory_budget(checked_bytes(static_cast<std::uint64_t>(cap) * static_cast<std::uint64_t>(cap),
                                    sizeof(double)),
                      fmt::format("EKF-SLAM covariance of {} state components", cap));
  Eigen::MatrixXd P = Eigen::MatrixXd::Zero(cap, cap);
  const Eigen::Index used = std::min(n_, P_.rows());  // P_ is empty before the first call
  P.topLeftCorner(used, used) = P_.topLeftCorner(used, used);
  P_.swap(P);
  Eigen::VectorXd l = Eigen::VectorXd::Zero(cap - kD);
  l.head(landmarks_.size()) = landmarks_;
  landmarks_.swap(l);
}

template <int Dim>
typename EkfSlam<Dim>::ReadingCovariance EkfSlam<Dim>::reading_noise() const {
  ReadingCovariance R = ReadingCovariance::Zero();
  R(0, 0) = options_.std_sensor_range * options_.std_sensor_range;
  R(1, 1) = options_.std_sensor_yaw * options_.std_sensor_yaw;
  if constexpr (kM == 3) R(2, 2) = options_.std_sensor_pitch * options_.std_sensor_pitch;
  return R;
}

template <int Dim>
void EkfSlam<Dim>::predict(const std::optional<EkfSlamOdometry<Dim>>& odometry) {
  Pose U;
  PoseCovariance Q = PoseCovariance::Zero();
  if (odometry && !options_.force_ignore_odometry) {
    ROVE_CHECK_FINITE(odometry->covariance);
    U = odometry->increment;
    Q = 0.5 * (odometry->covariance + odometry->covariance.transpose());
  } else {
    for (int i = 0; i < kD; ++i) {
      const double s = options_.stds_no_odometry[static_cast<std::size_t>(i)];
      Q(i, i) = s * s;
    }
  }
  // While the map is empty the robot's pose defines the map frame: the mean
  // moves, no uncertainty is added (MRPT skips the whole prediction then).
  // Otherwise the first landmarks would inherit the robot's uncertainty and
  // the map's orientation would be free to drift (an unfixed gauge).
  if (landmark_count() == 0) {
    pose_ = pose_ * U;
    return;
  }
  // X' = X·U: δ' = Adj(U⁻¹)·δ + ε (Solà et al. 2018, Eq. 177).
  const PoseCovariance F = U.inverse().Adj();
  auto P = P_.topLeftCorner(n_, n_);
  const Eigen::Index rest = n_ - kD;
  if (rest > 0) {
    const Eigen::MatrixXd cross = F * P.topRightCorner(kD, rest);
    P.topRightCorner(kD, rest) = cross;
    P.bottomLeftCorner(rest, kD) = cross.transpose();
  }
  const PoseCovariance Prr = F * P.template topLeftCorner<kD, kD>() * F.transpose() + Q;
  P.template topLeftCorner<kD, kD>() = 0.5 * (Prr + Prr.transpose());
  pose_ = pose_ * U;
}

template <int Dim>
bool EkfSlam<Dim>::linearize(std::size_t i, const Pose& T_rs, Linearization& lin) const {
  const Eigen::Index col = kD + static_cast<Eigen::Index>(i) * kL;
  const Point p_w = landmarks_.template segment<kL>(col - kD);
  const Point q = pose_.inverse() * p_w;  // robot frame
  const Point p_s = T_rs.inverse() * q;   // sensor frame
  Eigen::Matrix<double, kM, kL> Jz;
  if (!detail::spherical(p_s, lin.z, &Jz)) return false;
  const Eigen::Matrix<double, kM, kL> Jq = Jz * T_rs.rotation_matrix().transpose();
  lin.Hr = Jq * detail::inverse_action_jacobian(q);
  lin.Hl = Jq * pose_.rotation_matrix().transpose();
  lin.col = col;
  return true;
}

template <int Dim>
bool EkfSlam<Dim>::predict_reading(std::size_t i, const Pose& T_robot_sensor,
                                   Eigen::Matrix<double, kM, 1>* z,
                                   Eigen::Matrix<double, kM, kM>* S) const {
  ROVE_CHECK_LT(i, landmark_count());
  Linearization lin;
  if (!linearize(i, T_robot_sensor, lin)) return false;
  if (z) *z = lin.z;
  if (S) {
    const auto P = P_.topLeftCorner(n_, n_);
    const Eigen::Matrix<double, kM, kM> cross =
        lin.Hr * P.block(0, lin.col, kD, kL) * lin.Hl.transpose();
    *S = lin.Hr * P.template topLeftCorner<kD, kD>() * lin.Hr.transpose() + cross +
         cross.transpose() + lin.Hl * P.block(lin.col, lin.col, kL, kL) * lin.Hl.transpose() +
         reading_noise();
  }
  return true;
}

template <int Dim>
void EkfSlam<Dim>::pair_by_id(const EkfSlamFrame<Dim>& frame, EkfSlamStepResult& r,
                              std::vector<std::pair<int, int>>& pairs) const {
  std::unordered_map<std::int64_t, int> first_in_frame;
  for (std::size_t j = 0; j < frame.readings.size(); ++j) {
    const auto& rd = frame.readings[j];
    if (r.outcome[j] == ReadingOutcome::Skipped || rd.id < 0 || !options_.use_landmark_ids) {
      continue;
    }
    if (!first_in_frame.emplace(rd.id, static_cast<int>(j)).second) {
      r.outcome[j] = ReadingOutcome::Skipped;  // the ID was already read in this frame
      continue;
    }
    const auto it = index_of_id_.find(rd.id);
    if (it == index_of_id_.end()) {
      r.outcome[j] = ReadingOutcome::NewLandmark;
      continue;
    }
    Linearization lin;
    if (!linearize(static_cast<std::size_t>(it->second), frame.T_robot_sensor, lin)) {
      r.outcome[j] = ReadingOutcome::Skipped;  // at the sensor: no bearing
      continue;
    }
    r.outcome[j] = ReadingOutcome::PairedById;
    r.landmark[j] = it->second;
    pairs.emplace_back(static_cast<int>(j), it->second);
  }
}

template <int Dim>
void EkfSlam<Dim>::pair_by_association(const EkfSlamFrame<Dim>& frame, EkfSlamStepResult& r,
                                       std::vector<std::pair<int, int>>& pairs) const {
  std::vector<int> open;  // readings left for data association
  for (std::size_t j = 0; j < frame.readings.size(); ++j) {
    const auto& rd = frame.readings[j];
    const bool by_id = options_.use_landmark_ids && rd.id >= 0;
    if (r.outcome[j] == ReadingOutcome::Skipped || by_id) continue;
    r.outcome[j] = ReadingOutcome::NewLandmark;
    open.push_back(static_cast<int>(j));
  }
  if (open.empty() || landmark_count() == 0) return;
  std::vector<bool> taken(landmark_count(), false);
  for (const auto& [j, l] : pairs) taken[static_cast<std::size_t>(l)] = true;
  // Individual gates first (O(1) per landmark), then the joint covariance of
  // the landmarks that pass any of them: the others cannot be paired.
  std::vector<Linearization> lins;
  std::vector<int> candidates;
  const auto P = P_.topLeftCorner(n_, n_);
  std::vector<int> angles = {1};
  if (kM == 3) angles.push_back(2);
  for (std::size_t i = 0; i < landmark_count(); ++i) {
    if (taken[i]) continue;
    Linearization lin;
    Eigen::Matrix<double, kM, kM> Sii;
    if (!linearize(i, frame.T_robot_sensor, lin)) continue;
    predict_reading(i, frame.T_robot_sensor, nullptr, &Sii);
    bool any = false;
    for (std::size_t a = 0; a < open.size() && !any; ++a) {
      Eigen::Matrix<double, kM, 1> v = frame.readings[static_cast<std::size_t>(open[a])].z - lin.z;
      for (int c : angles) v[c] = wrap_to_pi(v[c]);
      any = individually_compatible(v, Sii, options_.data_association, ic_chi2_);
    }
    if (!any) continue;
    lins.push_back(lin);
    candidates.push_back(static_cast<int>(i));
  }
  const Eigen::Index n = static_cast<Eigen::Index>(candidates.size());
  if (n == 0) return;
  Eigen::MatrixXd Z(static_cast<Eigen::Index>(open.size()), kM), Y(n, kM);
  for (std::size_t a = 0; a < open.size(); ++a) {
    Z.row(static_cast<Eigen::Index>(a)) =
        frame.readings[static_cast<std::size_t>(open[a])].z.transpose();
  }
  // H_a·P (kM × n) from the robot and landmark rows only.
  std::vector<Eigen::Matrix<double, kM, Eigen::Dynamic>> HP(static_cast<std::size_t>(n));
  for (Eigen::Index a = 0; a < n; ++a) {
    const Linearization& l = lins[static_cast<std::size_t>(a)];
    Y.row(a) = l.z.transpose();
    HP[static_cast<std::size_t>(a)] =
        l.Hr * P.topRows(kD) + l.Hl * P.middleRows(l.col, kL);
  }
  Eigen::MatrixXd S(n * kM, n * kM);
  for (Eigen::Index a = 0; a < n; ++a) {
    for (Eigen::Index b = a; b < n; ++b) {
      const Linearization& lb = lins[static_cast<std::size_t>(b)];
      const auto& hp = HP[static_cast<std::size_t>(a)];
      Eigen::Matrix<double, kM, kM> s = hp.leftCols(kD) * lb.Hr.transpose() +
                                        hp.middleCols(lb.col, kL) * lb.Hl.transpose();
      if (a == b) s = 0.5 * (s + s.transpose()) + reading_noise();
      S.block(a * kM, b * kM, kM, kM) = s;
      S.block(b * kM, a * kM, kM, kM) = s.transpose();
    }
  }
  DataAssociationResult da = associate(Z, Y, S, angles, options_.data_association);
  for (std::size_t a = 0; a < open.size(); ++a) {
    const int p = da.pairing[a];
    if (p < 0) continue;
    const int j = open[a];
    const int l = candidates[static_cast<std::size_t>(p)];
    r.outcome[static_cast<std::size_t>(j)] = ReadingOutcome::Associated;
    r.landmark[static_cast<std::size_t>(j)] = l;
    pairs.emplace_back(j, l);
  }
  r.association = std::move(da);
}


template <int Dim>
bool EkfSlam<Dim>::kalman_update(const EkfSlamFrame<Dim>& frame,
                                 const std::vector<std::pair<int, int>>& pairs, double& nis) {
  const Eigen::Index k = static_cast<Eigen::Index>(pairs.size()), M = k * kM;
  auto P = P_.topLeftCorner(n_, n_);
  std::vector<Linearization> lins(pairs.size());
  Eigen::VectorXd nu(M);
  Eigen::MatrixXd PHt(n_, M);  // P·Hᵀ from the robot's and the landmark's columns only
  for (Eigen::Index a = 0; a < k; ++a) {
    const auto& [j, l] = pairs[static_cast<std::size_t>(a)];
    Linearization& lin = lins[static_cast<std::size_t>(a)];
    if (!linearize(static_cast<std::size_t>(l), frame.T_robot_sensor, lin)) return false;
    Eigen::Matrix<double, kM, 1> v = frame.readings[static_cast<std::size_t>(j)].z - lin.z;
    for (int c = 1; c < kM; ++c) v[c] = wrap_to_pi(v[c]);
    nu.template segment<kM>(a * kM) = v;
    PHt.middleCols(a * kM, kM).noalias() =
        P.leftCols(kD) * lin.Hr.transpose() + P.middleCols(lin.col, kL) * lin.Hl.transpose();
  }
  Eigen::MatrixXd S(M, M);  // H·(P·Hᵀ) + R from the same rows
  for (Eigen::Index a = 0; a < k; ++a) {
    const Linearization& lin = lins[static_cast<std::size_t>(a)];
    S.middleRows(a * kM, kM).noalias() =
        lin.Hr * PHt.topRows(kD) + lin.Hl * PHt.middleRows(lin.col, kL);
  }
  S = 0.5 * (S + S.transpose()).eval();
  for (Eigen::Index a = 0; a < k; ++a) S.block(a * kM, a * kM, kM, kM) += reading_noise();
  const Eigen::LLT<Eigen::MatrixXd> llt(S);
  if (llt.info() != Eigen::Success) return false;
  // W = P·Hᵀ·L⁻ᵀ: the gain is W·L⁻¹ and P⁺ = P − W·Wᵀ (a symmetric rank-M update).
  const Eigen::MatrixXd W = llt.matrixL().solve(PHt.transpose()).transpose();
  const Eigen::VectorXd w = llt.matrixL().solve(nu);
  nis += w.squaredNorm();
  const Eigen::VectorXd dx = W * w;
  P.template selfadjointView<Eigen::Lower>().rankUpdate(W, -1.0);
  for (Eigen::Index c = 1; c < n_; ++c) P.col(c).head(c) = P.row(c).head(c).transpose();
  // Reset of the error state: the posterior error ε about X is moved to the
  // tangent at X' = X·exp(δx): X·exp(δx + ε) = X'·exp(Jr(δx)·ε) to first
  // order, so the robot's rows and columns are mapped by Jr(δx) (O(n); the
  // step is omitted by many EKF-SLAM implementations, and its absence bends
  // the map when the corrections are large, as without odometry).
  const typename Pose::Tangent dr = dx.template head<kD>();
  const PoseCovariance Jr = Pose::right_jacobian(dr);
  const Eigen::MatrixXd rows = Jr * P.topRows(kD);
  P.topRows(kD) = rows;
  P.leftCols(kD) = P.topRows(kD).transpose().eval();
  P.template topLeftCorner<kD, kD>() =
      (rows.leftCols(kD) * Jr.transpose() + (rows.leftCols(kD) * Jr.transpose()).transpose()) / 2;
  pose_ = pose_.oplus(dr);
  landmarks_.head(n_ - kD) += dx.tail(n_ - kD);
  return true;
}

template <int Dim>
void EkfSlam<Dim>::add_landmark(const EkfSlamReading<Dim>& reading, const Pose& T_rs) {
  Eigen::Matrix<double, kL, kM> Js;
  const Point p_s = detail::from_spherical(reading.z, Js);
  const Point q = T_rs * p_s;
  typename Pose::ActionJacobian G_r;
  Eigen::Matrix<double, kL, kL> R_wr;
  const Point p_w = pose_.act(q, &G_r, &R_wr);
  const Eigen::Matrix<double, kL, kM> G_z = R_wr * T_rs.rotation_matrix() * Js;
  const Eigen::Index col = n_;
  reserve(n_ + kL);
  auto P = P_.topLeftCorner(n_ + kL, n_ + kL);
  // P_l· = G_r·P_δ·, P_ll = G_r·P_δδ·G_rᵀ + G_z·R·G_zᵀ.
  const Eigen::MatrixXd cross = G_r * P.topLeftCorner(kD, n_);
  P.block(col, 0, kL, n_) = cross;
  P.block(0, col, n_, kL) = cross.transpose();
  const PointCovariance Pll =
      cross.leftCols(kD) * G_r.transpose() + G_z * reading_noise() * G_z.transpose();
  P.block(col, col, kL, kL) = 0.5 * (Pll + Pll.transpose());
  landmarks_.template segment<kL>(col - kD) = p_w;
  n_ += kL;
  const int index = static_cast<int>(ids_.size());
  ids_.push_back(reading.id);
  seen_.push_back(1);
  if (reading.id >= 0) index_of_id_.emplace(reading.id, index);
}

template <int Dim>
EkfSlamStepResult EkfSlam<Dim>::update(const EkfSlamFrame<Dim>& frame) {
  EkfSlamStepResult r;
  const std::size_t k = frame.readings.size();
  r.outcome.assign(k, ReadingOutcome::NewLandmark);
  r.landmark.assign(k, -1);
  for (std::size_t j = 0; j < k; ++j) {
    const auto& z = frame.readings[j].z;
    ROVE_CHECK_MSG(z.allFinite(), "reading {} of the frame is not finite (range {}, yaw {})", j,
                   z[0], z[1]);
    if (!(z[0] > detail::kMinBearingRadius)) r.outcome[j] = ReadingOutcome::Skipped;
  }
  std::vector<std::pair<int, int>> pairs;
  pair_by_id(frame, r, pairs);
  pair_by_association(frame, r, pairs);
  bool ok = true;
  if (!pairs.empty()) {
    if (options_.update == EkfSlamUpdate::Batch) {
      ok = kalman_update(frame, pairs, r.nis);
    } else {
      for (const auto& p : pairs) ok = kalman_update(frame, {p}, r.nis) && ok;
    }
    r.nis_dof = pairs.size() * kM;
  }
  r.termination = ok ? EkfSlamTermination::Updated : EkfSlamTermination::NotPositiveDefinite;
  for (const auto& [j, l] : pairs) ++seen_[static_cast<std::size_t>(l)];
  for (std::size_t j = 0; j < k; ++j) {
    switch (r.outcome[j]) {
      case ReadingOutcome::PairedById: ++r.by_id; break;
      case ReadingOutcome::Associated: ++r.associated; break;
      case ReadingOutcome::Skipped: ++r.skipped; break;
      case ReadingOutcome::NewLandmark:
        r.landmark[j] = static_cast<int>(landmark_count());
        add_landmark(frame.readings[j], frame.T_robot_sensor);
        ++r.created;
        break;
    }
  }
  r.message = fmt::format("{} readings: {} paired by ID, {} associated, {} new, {} skipped; NIS "
                          "{:.3f} over {} values{}",
                          k, r.by_id, r.associated, r.created, r.skipped, r.nis, r.nis_dof,
                          ok ? "" : "; update skipped: innovation covariance not positive definite");
  return r;
}

template <int Dim>
EkfSlamStepResult EkfSlam<Dim>::step(const std::optional<EkfSlamOdometry<Dim>>& odometry,
                                     const EkfSlamFrame<Dim>& frame) {
  predict(odometry);
  return update(frame);
}

template <int Dim>
typename EkfSlam<Dim>::PoseCovariance EkfSlam<Dim>::pose_covariance() const {
  return P_.template topLeftCorner<kD, kD>();
}

template <int Dim>
typename EkfSlam<Dim>::Point EkfSlam<Dim>::landmark(std::size_t i) const {
  ROVE_CHECK_LT(i, landmark_count());
  return landmarks_.template segment<kL>(static_cast<Eigen::Index>(i) * kL);
}

template <int Dim>
typename EkfSlam<Dim>::PointCovariance EkfSlam<Dim>::landmark_covariance(std::size_t i) const {
  ROVE_CHECK_LT(i, landmark_count());
  const Eigen::Index c = kD + static_cast<Eigen::Index>(i) * kL;
  return P_.template block<kL, kL>(c, c);
}

template <int Dim>
std::int64_t EkfSlam<Dim>::landmark_id(std::size_t i) const {
  ROVE_CHECK_LT(i, landmark_count());
  return ids_[i];
}

template <int Dim>
std::size_t EkfSlam<Dim>::landmark_observations(std::size_t i) const {
  ROVE_CHECK_LT(i, landmark_count());
  return seen_[i];
}

template <int Dim>
Eigen::MatrixXd EkfSlam<Dim>::covariance() const {
  return P_.topLeftCorner(n_, n_);
}

template class EkfSlam<2>;
template class EkfSlam<3>;

std::string_view to_string(ReadingOutcome outcome) noexcept {
  switch (outcome) {
    case ReadingOutcome::PairedById: return "paired-by-id";
    case ReadingOutcome::Associated: return "associated";
    case ReadingOutcome::NewLandmark: return "new-landmark";
    case ReadingOutcome::Skipped: return "skipped";
  }
  return "?";
}

}  // namespace rove
