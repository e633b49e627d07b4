#pragma once
/// \file
/// Checks and linear algebra shared by rove's Gaussian pose PDFs: validation
/// of covariance / information matrices, a square root that works for
/// positive semi-definite matrices (used to draw samples), Mahalanobis
/// distances and Gaussian log-densities.

#include <random>
#include <string_view>

#include <Eigen/Core>

namespace rove {

/// Relative tolerance of the checks on covariance and information matrices:
/// asymmetry and negative eigenvalues up to this fraction of the largest
/// absolute entry are accepted as round-off.
inline constexpr double kCovarianceTolerance = 1e-9;

/// Throws rove::InvalidArgument unless `m` is square, finite, symmetric and
/// positive semi-definite within kCovarianceTolerance. `what` names the matrix
/// in the message (e.g. "Pose2Gaussian covariance").
void check_covariance(const Eigen::Ref<const Eigen::MatrixXd>& m, std::string_view what);

/// True if the square, symmetric matrix `m` is positive definite: Cholesky
/// succeeds and the smallest eigenvalue exceeds kCovarianceTolerance times the
/// largest one.
bool is_positive_definite(const Eigen::Ref<const Eigen::MatrixXd>& m);

/// Inverse of a symmetric positive-definite matrix (through Cholesky), the
/// result symmetrized. Throws rove::InvalidArgument naming `what` if `m` is
/// not positive definite (see is_positive_definite).
Eigen::MatrixXd spd_inverse(const Eigen::Ref<const Eigen::MatrixXd>& m, std::string_view what);

/// A factor S with S·Sᵀ = m of a symmetric positive semi-definite matrix,
/// from its eigen-decomposition (S = V·sqrt(Λ)); eigenvalues that are
/// negative by round-off are clipped to zero, so a zero matrix gives S = 0.
/// Precondition: m passes check_covariance.
Eigen::MatrixXd psd_sqrt(const Eigen::Ref<const Eigen::MatrixXd>& m);

/// Draws z ~ N(0, I) of size `n` from `rng` (std::normal_distribution).
Eigen::VectorXd standard_normal_vector(std::mt19937_64& rng, Eigen::Index n);

/// Mahalanobis distance sqrt(dᵀ C⁺ d) of the difference `d` under the
/// positive semi-definite covariance `cov` (C⁺: pseudo-inverse). If `d` has a
/// component along a direction of zero variance (relative tolerance
/// kCovarianceTolerance on both the eigenvalue and the component) the
/// distance is +infinity; d = 0 always gives 0.
double mahalanobis_distance(const Eigen::Ref<const Eigen::VectorXd>& d,
                            const Eigen::Ref<const Eigen::MatrixXd>& cov);

/// Natural log of the density of N(0, cov) at `d`:
/// −½ (dᵀC⁻¹d + log det(2πC)). Throws rove::InvalidArgument if `cov` is not
/// positive definite (a degenerate Gaussian has no density).
double gaussian_log_density(const Eigen::Ref<const Eigen::VectorXd>& d,
                            const Eigen::Ref<const Eigen::MatrixXd>& cov);

/// Natural log of the density at `d` of the Gaussian with zero mean and
/// information (inverse covariance) `information`:
/// −½ (dᵀΛd − log det(Λ) + n log 2π). Throws rove::InvalidArgument if
/// `information` is not positive definite.
double gaussian_log_density_information(const Eigen::Ref<const Eigen::VectorXd>& d,
                                        const Eigen::Ref<const Eigen::MatrixXd>& information);

}  // namespace rove
