#pragma once
/// \file
/// Data association of observations with predicted landmark observations
/// that carry a full joint covariance: nearest neighbour and joint
/// compatibility branch and bound (JCBB), with a Mahalanobis or a maximum
/// likelihood metric, under MRPT's option names (`data_assoc_method`,
/// `data_assoc_metric`, `data_assoc_IC_metric`, `data_assoc_IC_chi2_thres`,
/// `data_assoc_IC_ml_threshold`).
///
/// Individual compatibility (IC) of observation j with prediction i: the
/// squared Mahalanobis distance d² = νᵀ S_ii⁻¹ ν of ν = z_j ⊖ ŷ_i is below
/// χ²(p, dim z) (IC metric Mahalanobis), or the log-likelihood
/// −d²/2 − log √det(2π S_ii) exceeds the threshold (IC metric ML).
///
/// - NearestNeighbor: MRPT's greedy rule: observations are taken in the
///   order of their best compatible prediction (smallest d², or largest
///   likelihood), each gets its best prediction not yet taken.
/// - Jcbb: Neira & Tardós, "Data association in stochastic mapping using
///   the joint compatibility test", IEEE T-RA 17(6), 2001: the hypothesis
///   with the most pairings whose every partial hypothesis (pairings of the
///   first observations, in order) is jointly compatible, D²_H = ν_Hᵀ C_H⁻¹
///   ν_H < χ²(p, dim z · |H|) with C_H the joint innovation covariance of
///   the paired predictions (cross-covariances included); ties go to the
///   smaller D_H² (Mahalanobis) or the larger joint log-likelihood (ML).
///   MRPT's JCBB omits the joint test and keeps the largest individually
///   compatible hypothesis; rove applies the test the method is named for.

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "rove/core/config_section.h"

namespace rove {

/// How observations are paired with predictions (MRPT's TDataAssociationMethod).
enum class DataAssociationMethod : std::uint8_t {
  /// MRPT's assocNN: greedy nearest neighbour.
  NearestNeighbor = 0,
  /// MRPT's assocJCBB: joint compatibility branch and bound.
  Jcbb = 1,
};

/// What "closer" means (MRPT's TDataAssociationMetric).
enum class DataAssociationMetric : std::uint8_t {
  /// MRPT's metricMaha: squared Mahalanobis distance, smaller is better.
  Mahalanobis = 0,
  /// MRPT's metricML: Gaussian log-likelihood of the innovation, larger is better.
  MaximumLikelihood = 1,
};

/// "nearest-neighbor" or "jcbb".
std::string_view to_string(DataAssociationMethod method) noexcept;
/// "mahalanobis" or "maximum-likelihood".
std::string_view to_string(DataAssociationMetric metric) noexcept;

/// Options of associate().
struct DataAssociationOptions {
  /// Pairing method (`data_assoc_method`: assocNN, assocJCBB). Default NN.
  DataAssociationMethod method = DataAssociationMethod::NearestNeighbor;
  /// Metric choosing among compatible pairings (`data_assoc_metric`:
  /// metricMaha, metricML). Default Mahalanobis.
  DataAssociationMetric metric = DataAssociationMetric::Mahalanobis;
  /// Metric of the individual compatibility test (`data_assoc_IC_metric`).
  DataAssociationMetric ic_metric = DataAssociationMetric::Mahalanobis;
  /// χ² probability of the compatibility tests (`data_assoc_IC_chi2_thres`),
  /// in (0, 1). Default 0.99.
  double chi2_probability = 0.99;
  /// Log-likelihood threshold of the ML compatibility test
  /// (`data_assoc_IC_ml_threshold`). Default 0.
  double ml_threshold = 0.0;
  /// JCBB: most search nodes before the best hypothesis found so far is
  /// returned (termination NodeLimit), ≥ 1 (rove `data_assoc_JCBB_max_nodes`).
  std::size_t max_jcbb_nodes = 1'000'000;

  /// Reads the keys above from `section` (MRPT's enum names or numbers).
  /// Throws ConfigError naming the key for a bad value.
  static DataAssociationOptions from_config(const ConfigSection& section);
  /// Throws InvalidArgument naming the first field out of range.
  void check() const;
};

/// How associate() ended.
enum class DataAssociationTermination : std::uint8_t {
  /// The search completed.
  Completed,
  /// JCBB stopped at max_jcbb_nodes; the best hypothesis so far is returned.
  NodeLimit,
};

/// The pairing of observations with predictions.
struct DataAssociationResult {
  /// How the search ended.
  DataAssociationTermination termination = DataAssociationTermination::Completed;
  /// One line: pairings, nodes, joint distance.
  std::string message;
  /// Per observation: the index of its prediction, or −1 when unpaired.
  std::vector<int> pairing;
  /// Individual compatibility, predictions × observations.
  Eigen::Matrix<bool, Eigen::Dynamic, Eigen::Dynamic> compatible;
  /// Squared Mahalanobis distances, predictions × observations.
  Eigen::MatrixXd mahalanobis2;
  /// The hypothesis' joint D² (Mahalanobis) of its pairings (0 if none).
  double joint_mahalanobis2 = 0.0;
  /// JCBB search nodes visited (0 for NN).
  std::size_t nodes = 0;
  /// Number of paired observations.
  std::size_t paired() const;
};

/// Pairs observations with predictions.
///
/// `observations`: k × m (one observation a row); `predictions`: n × m;
/// `covariance`: the nm × nm joint covariance of the innovations of the
/// predictions (S = H P Hᵀ + R, blocks in prediction order; only the
/// diagonal blocks are read by NN). `angle_components`: columns that are
/// angles, whose differences are wrapped to (−π, π].
/// Preconditions (InvalidArgument): sizes agree, values finite, options
/// valid. A diagonal block that is not positive definite makes its
/// prediction incompatible with every observation.
DataAssociationResult associate(const Eigen::MatrixXd& observations,
                                const Eigen::MatrixXd& predictions,
                                const Eigen::MatrixXd& covariance,
                                const std::vector<int>& angle_components,
                                const DataAssociationOptions& options);

/// The individual compatibility test of an innovation `v` (angles already
/// wrapped) with covariance `S` under options' IC metric and thresholds,
/// `chi2` being chi_square_quantile(options.chi2_probability, v.size())
/// (computed once by the caller); false if S is not positive definite.
/// Sizes must agree (InvalidArgument).
bool individually_compatible(const Eigen::VectorXd& v, const Eigen::MatrixXd& S,
                             const DataAssociationOptions& options, double chi2);

/// The joint squared Mahalanobis distance D² and Gaussian log-likelihood of
/// a hypothesis (`pairing` as in DataAssociationResult; unpaired entries
/// skipped): the stacked innovation against the joint covariance of the
/// paired predictions. Returns false (outputs untouched) if that covariance
/// is not positive definite. Same preconditions as associate().
bool joint_distance(const Eigen::MatrixXd& observations, const Eigen::MatrixXd& predictions,
                    const Eigen::MatrixXd& covariance, const std::vector<int>& angle_components,
                    const std::vector<int>& pairing, double* mahalanobis2,
                    double* log_likelihood);

}  // namespace rove
