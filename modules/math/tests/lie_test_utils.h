#pragma once
// Shared helpers for the Lie-group tests: samplers with fixed seeds, a
// central-difference Jacobian on manifolds, an independent matrix exponential
// and the generic property checks every group must pass.
//
// Tolerances. Round trips (exp∘log, log∘exp, X·X⁻¹): 1e-9 (double) and 2e-4
// (float), relative to max(1, magnitude). Analytic Jacobians are compared
// with central differences taken in double precision (step 1e-6, truncation
// error ~1e-12): tolerance 1e-6 for double, 5e-4 for float (the float
// analytic Jacobian against the double-precision numeric reference), again
// relative to max(1, largest entry).

#include <cmath>
#include <numbers>
#include <random>
#include <string>
#include <type_traits>
#include <vector>

#include <Eigen/Core>
#include <gtest/gtest.h>

#include "rove/core/error.h"
#include "rove/math/types.h"

namespace rove::test {

using ScalarTypes = ::testing::Types<float, double>;

/// Tolerance for round trips in scalar T.
template <typename T>
constexpr double round_trip_tol() {
  return std::is_same_v<T, float> ? 2e-4 : 1e-9;
}
/// Tolerance for analytic vs numeric Jacobians in scalar T.
template <typename T>
constexpr double jacobian_tol() {
  return std::is_same_v<T, float> ? 5e-4 : 1e-6;
}

/// Max-abs comparison of two matrices with tolerance tol·max(1, max|B|).
template <typename A, typename B>
::testing::AssertionResult matrices_near(const A& a_in, const B& b_in, double tol) {
  const Eigen::MatrixXd a = a_in.template cast<double>();
  const Eigen::MatrixXd b = b_in.template cast<double>();
  if (a.rows() != b.rows() || a.cols() != b.cols()) {
    return ::testing::AssertionFailure() << "size mismatch";
  }
  const double scale = std::max(1.0, b.cwiseAbs().maxCoeff());
  const double err = (a - b).cwiseAbs().maxCoeff();
  if (err <= tol * scale) return ::testing::AssertionSuccess();
  Eigen::IOFormat fmt(8, 0, ", ", "\n", "[", "]");
  return ::testing::AssertionFailure() << "max |a - b| = " << err << " > " << tol * scale
                                       << "\na =\n"
                                       << a.format(fmt) << "\nb =\n"
                                       << b.format(fmt);
}

// ---- manifold helpers for numeric differentiation --------------------------

template <typename X>
constexpr bool kIsGroup = requires { X::kDof; };

template <typename X>
constexpr int dim_of() {
  if constexpr (kIsGroup<X>) {
    return X::kDof;
  } else {
    return X::RowsAtCompileTime;
  }
}

template <typename X>
X retract(const X& x, const Eigen::VectorXd& d) {
  if constexpr (kIsGroup<X>) {
    return x.oplus(typename X::Tangent(d));
  } else {
    return x + X(d);
  }
}

template <typename X>
Eigen::VectorXd local(const X& y, const X& x) {
  if constexpr (kIsGroup<X>) {
    return y.ominus(x);
  } else {
    return y - x;
  }
}

/// Central-difference Jacobian of f at x: column i is
/// (f(x ⊕ h eᵢ) ⊖ f(x) − f(x ⊕ −h eᵢ) ⊖ f(x)) / 2h, with ⊕/⊖ the right
/// operations on groups and +/− on vectors.
template <typename F, typename X>
Eigen::MatrixXd numeric_jacobian(F&& f, const X& x, double h = 1e-6) {
  using Y = std::decay_t<decltype(f(x))>;
  const Y y0 = f(x);
  const int n = dim_of<X>();
  const int m = dim_of<Y>();
  Eigen::MatrixXd J(m, n);
  for (int i = 0; i < n; ++i) {
    Eigen::VectorXd d = Eigen::VectorXd::Zero(n);
    d(i) = h;
    J.col(i) = (local(f(retract(x, d)), y0) - local(f(retract(x, Eigen::VectorXd(-d))), y0)) /
               (2.0 * h);
  }
  return J;
}

/// Matrix exponential by scaling and squaring of the Taylor series, in
/// double: an oracle for exp(hat(ξ)) independent of the closed forms.
inline Eigen::MatrixXd matrix_exponential(const Eigen::MatrixXd& A) {
  const double norm = A.cwiseAbs().rowwise().sum().maxCoeff();
  int squarings = 0;
  if (norm > 0.5) squarings = static_cast<int>(std::ceil(std::log2(norm / 0.5)));
  const Eigen::MatrixXd B = A / std::pow(2.0, squarings);
  Eigen::MatrixXd result = Eigen::MatrixXd::Identity(A.rows(), A.cols());
  Eigen::MatrixXd term = result;
  for (int k = 1; k <= 30; ++k) {
    term = term * B / static_cast<double>(k);
    result += term;
  }
  for (int i = 0; i < squarings; ++i) result = result * result;
  return result;
}

// ---- samplers --------------------------------------------------------------

/// Number of rotation components of group G's tangent (1 in 2D, 3 in 3D).
template <typename G>
constexpr int rotation_dim() {
  return G::Point::RowsAtCompileTime == 2 ? 1 : 3;
}

/// Tangent with rotation angle `angle` about a random axis (2D: random sign)
/// and translation uniform in [−trans, trans] per axis.
template <typename G>
typename G::Tangent tangent_with_angle(std::mt19937& rng, double angle, double trans = 2.0) {
  using T = typename G::Scalar;
  constexpr int kRot = rotation_dim<G>();
  constexpr int kTrans = G::kDof - kRot;
  std::normal_distribution<double> normal;
  std::uniform_real_distribution<double> uni(-trans, trans);
  typename G::Tangent xi;
  for (int i = 0; i < kTrans; ++i) xi(i) = static_cast<T>(uni(rng));
  Eigen::VectorXd axis(kRot);
  if constexpr (kRot == 1) {
    axis(0) = (rng() % 2 == 0) ? 1.0 : -1.0;
  } else {
    for (int i = 0; i < kRot; ++i) axis(i) = normal(rng);
    axis.normalize();
  }
  for (int i = 0; i < kRot; ++i) xi(kTrans + i) = static_cast<T>(angle * axis(i));
  return xi;
}

/// Rotation angles exercising every branch: zero, tiny (Taylor), both sides
/// of each small-angle threshold, moderate, and close to π (with `pi_margin`).
inline std::vector<double> test_angles(double pi_margin) {
  return {0.0,  1e-9, 1e-6, 1e-3, 0.049, 0.051, 0.19, 0.21,
          0.5,  1.0,  2.0,  3.0,  std::numbers::pi - pi_margin};
}

/// Tangent samples: every test angle, plus `n_random` angles uniform in
/// [0, π − pi_margin). Fixed seed.
template <typename G>
std::vector<typename G::Tangent> tangent_samples(double pi_margin, int n_random = 40,
                                                 unsigned seed = 12345) {
  std::mt19937 rng(seed);
  std::vector<typename G::Tangent> out;
  for (double a : test_angles(pi_margin)) out.push_back(tangent_with_angle<G>(rng, a));
  std::uniform_real_distribution<double> angle(0.0, std::numbers::pi - pi_margin);
  for (int i = 0; i < n_random; ++i) out.push_back(tangent_with_angle<G>(rng, angle(rng)));
  return out;
}

/// Random group elements (exp of tangent_samples).
template <typename G>
std::vector<G> group_samples(double pi_margin, int n_random = 40, unsigned seed = 777) {
  std::vector<G> out;
  for (const auto& xi : tangent_samples<G>(pi_margin, n_random, seed)) out.push_back(G::exp(xi));
  return out;
}

/// Margin from π for round-trip samples (log∘exp is unique only below π).
template <typename T>
constexpr double near_pi_margin() {
  return std::is_same_v<T, float> ? 1e-3 : 1e-7;
}

// ---- generic property checks ------------------------------------------------

/// log(exp(ξ)) = ξ for |rotation| < π, and exp(log(X)) = X.
template <typename G>
void check_exp_log_round_trips() {
  using T = typename G::Scalar;
  const double tol = round_trip_tol<T>();
  for (const auto& xi : tangent_samples<G>(near_pi_margin<T>())) {
    const typename G::Tangent back = G::exp(xi).log();
    EXPECT_TRUE(matrices_near(back, xi, tol)) << "xi = " << xi.transpose();
  }
  for (const G& X : group_samples<G>(near_pi_margin<T>())) {
    EXPECT_TRUE(matrices_near(G::exp(X.log()).matrix(), X.matrix(), tol));
  }
}

/// exp(ξ).matrix() equals the matrix exponential of hat(ξ); vee(hat(ξ)) = ξ.
template <typename G>
void check_hat_vee_and_matrix_exponential() {
  using T = typename G::Scalar;
  const double tol = round_trip_tol<T>();
  for (const auto& xi : tangent_samples<G>(1e-2)) {
    EXPECT_TRUE(matrices_near(G::vee(G::hat(xi)), xi, 0.0));
    const Eigen::MatrixXd expected = matrix_exponential(G::hat(xi).template cast<double>());
    EXPECT_TRUE(matrices_near(G::exp(xi).matrix(), expected, tol)) << "xi = " << xi.transpose();
  }
}

/// Associativity, identity, inverse, and matrix() as a homomorphism.
template <typename G>
void check_group_axioms() {
  using T = typename G::Scalar;
  const double tol = round_trip_tol<T>();
  const auto xs = group_samples<G>(1e-2, 20, 1);
  const auto ys = group_samples<G>(1e-2, 20, 2);
  const auto zs = group_samples<G>(1e-2, 20, 3);
  for (std::size_t i = 0; i < xs.size(); ++i) {
    const G& X = xs[i];
    const G& Y = ys[i];
    const G& Z = zs[i];
    EXPECT_TRUE(matrices_near(((X * Y) * Z).matrix(), (X * (Y * Z)).matrix(), tol));
    EXPECT_TRUE(matrices_near((X * X.inverse()).matrix(), G::identity().matrix(), tol));
    EXPECT_TRUE(matrices_near((X.inverse() * X).matrix(), G::identity().matrix(), tol));
    EXPECT_TRUE(matrices_near((X * G::identity()).matrix(), X.matrix(), tol));
    EXPECT_TRUE(matrices_near((X * Y).matrix(), X.matrix() * Y.matrix(), tol));
    EXPECT_TRUE(matrices_near(X.inverse().matrix(), X.matrix().inverse(), tol));
    EXPECT_TRUE((X * Y).is_approx(X * Y));
  }
}

/// Action on points agrees with the homogeneous matrix.
template <typename G>
void check_action_matches_matrix() {
  using T = typename G::Scalar;
  constexpr int kN = G::Point::RowsAtCompileTime;
  const double tol = round_trip_tol<T>();
  std::mt19937 rng(99);
  std::uniform_real_distribution<double> uni(-5.0, 5.0);
  for (const G& X : group_samples<G>(1e-2, 20)) {
    typename G::Point p;
    for (int i = 0; i < kN; ++i) p(i) = static_cast<T>(uni(rng));
    const auto M = X.matrix();
    Eigen::Matrix<T, kN, 1> expected;
    if constexpr (M.RowsAtCompileTime == kN) {
      expected = M * p;  // rotation groups
    } else {
      expected = M.template topLeftCorner<kN, kN>() * p + M.template topRightCorner<kN, 1>();
    }
    EXPECT_TRUE(matrices_near(X * p, expected, tol));
    EXPECT_TRUE(matrices_near(X.act(p), expected, tol));
  }
}

/// X·exp(ξ)·X⁻¹ = exp(Adj(X)·ξ).
template <typename G>
void check_adjoint() {
  using T = typename G::Scalar;
  const double tol = round_trip_tol<T>() * 10;
  const auto xs = group_samples<G>(1e-2, 20, 5);
  const auto xis = tangent_samples<G>(1e-2, 20, 6);
  for (std::size_t i = 0; i < xs.size(); ++i) {
    const G& X = xs[i];
    const typename G::Tangent xi = xis[i] * T(0.5);
    const G lhs = X * G::exp(xi) * X.inverse();
    const G rhs = G::exp(typename G::Tangent(X.Adj() * xi));
    EXPECT_TRUE(matrices_near(lhs.matrix(), rhs.matrix(), tol));
  }
}

/// Every analytic Jacobian against a central difference in double precision.
template <typename G>
void check_jacobians() {
  using T = typename G::Scalar;
  using Gd = std::decay_t<decltype(std::declval<G>().template cast<double>())>;
  using Td = typename Gd::Tangent;
  using Pd = typename Gd::Point;
  using J = typename G::Jacobian;
  constexpr int kN = G::Point::RowsAtCompileTime;
  const double tol = jacobian_tol<T>();
  const auto xis = tangent_samples<G>(1e-2, 30, 11);
  const auto ys = group_samples<G>(1e-2, 30, 12);
  std::mt19937 rng(13);
  std::uniform_real_distribution<double> uni(-3.0, 3.0);
  for (std::size_t i = 0; i < xis.size(); ++i) {
    const typename G::Tangent xi = xis[i];
    const Td xid = xi.template cast<double>();
    const G X = G::exp(xi);
    const Gd Xd = X.template cast<double>();
    const Gd Yd = ys[i].template cast<double>();

    // exp: d exp(ξ)/dξ = Jr(ξ); left Jacobian via log(exp(ξ + δ)·exp(ξ)⁻¹).
    J Jr;
    G::exp(xi, &Jr);
    const auto exp_d = [](const Td& v) { return Gd::exp(v); };
    const Eigen::MatrixXd Jr_num = numeric_jacobian(exp_d, xid);
    EXPECT_TRUE(matrices_near(Jr, Jr_num, tol)) << "Jr at " << xi.transpose();
    EXPECT_TRUE(matrices_near(G::right_jacobian(xi), Jr_num, tol));
    const Gd X0_inv = Gd::exp(xid).inverse();
    const Eigen::MatrixXd Jl_num =
        numeric_jacobian([&](const Td& v) { return Gd::exp(v) * X0_inv; }, xid);
    EXPECT_TRUE(matrices_near(G::left_jacobian(xi), Jl_num, tol)) << "Jl at " << xi.transpose();
    // Solà et al. 2018, Sec. III: Jl(ξ) = Adj(exp ξ)·Jr(ξ) and Jl(ξ) = Jr(−ξ).
    EXPECT_TRUE(matrices_near(G::left_jacobian(xi), X.Adj() * Jr, tol));
    EXPECT_TRUE(matrices_near(G::left_jacobian(xi), G::right_jacobian(-xi), tol));
    // Inverses.
    const J I = J::Identity();
    EXPECT_TRUE(matrices_near(G::right_jacobian_inverse(xi) * Jr, I, tol));
    EXPECT_TRUE(matrices_near(G::left_jacobian_inverse(xi) * G::left_jacobian(xi), I, tol));

    // log: d log(X ⊕ δ)/dδ = Jr⁻¹(log X).
    J Jlog;
    const typename G::Tangent lx = X.log(&Jlog);
    const Eigen::MatrixXd Jlog_num =
        numeric_jacobian([](const Gd& g) -> Td { return g.log(); }, Xd);
    EXPECT_TRUE(matrices_near(Jlog, Jlog_num, tol)) << "Jr_inv at " << lx.transpose();

    // inverse.
    J Jinv;
    X.inverse(&Jinv);
    EXPECT_TRUE(
        matrices_near(Jinv, numeric_jacobian([](const Gd& g) { return g.inverse(); }, Xd), tol));

    // compose.
    J Jc_this, Jc_other;
    const G Y = ys[i];
    X.compose(Y, &Jc_this, &Jc_other);
    EXPECT_TRUE(matrices_near(
        Jc_this, numeric_jacobian([&](const Gd& g) { return g * Yd; }, Xd), tol));
    EXPECT_TRUE(matrices_near(
        Jc_other, numeric_jacobian([&](const Gd& g) { return Xd * g; }, Yd), tol));

    // action.
    typename G::Point p;
    for (int k = 0; k < kN; ++k) p(k) = static_cast<T>(uni(rng));
    const Pd pd = p.template cast<double>();
    typename G::ActionJacobian J_pose;
    Eigen::Matrix<T, kN, kN> J_point;
    X.act(p, &J_pose, &J_point);
    EXPECT_TRUE(matrices_near(
        J_pose, numeric_jacobian([&](const Gd& g) -> Pd { return g * pd; }, Xd), tol));
    EXPECT_TRUE(matrices_near(
        J_point, numeric_jacobian([&](const Pd& q) -> Pd { return Xd * q; }, pd), tol));
  }
}

}  // namespace rove::test
