#pragma once
/// \file
/// SE2<T>: planar rigid transforms as a Lie group, with the exp/log, Adjoint
/// and Jacobians of Solà, Deray, Atchuthan, "A micro Lie theory for state
/// estimation in robotics" (2018, arXiv:1812.01537), Appendix C; equation
/// numbers below refer to that paper.
///
/// Conventions (docs/conventions.md): tangent ξ = [rho_x, rho_y, theta]
/// (meters, meters, radians), translation first; perturbations on the right,
/// X ⊕ δ = X · exp(δ), Y ⊖ X = log(X⁻¹ · Y). T_a_b maps points of frame b
/// into frame a.

#include <algorithm>
#include <cmath>
#include <numbers>

#include <Eigen/Core>

#include "rove/core/check.h"
#include "rove/math/detail/lie_coefficients.h"
#include "rove/math/so2.h"
#include "rove/math/types.h"

namespace rove {

/// A planar rigid transform (R(θ), t) ∈ SE(2): p ↦ R·p + t. Plain value
/// type; thread-compatible.
template <LieScalar T>
class SE2 {
 public:
  using Scalar = T;
  /// Degrees of freedom.
  static constexpr int kDof = 3;
  /// Tangent [rho_x, rho_y, theta] (m, m, rad).
  using Tangent = Vector3<T>;
  /// Jacobians between tangent spaces (3x3, same ordering as Tangent).
  using Jacobian = Matrix3<T>;
  /// Point in R².
  using Point = Vector2<T>;
  /// Lie-algebra element (3x3, [[0, −θ, ρx]; [θ, 0, ρy]; [0, 0, 0]]).
  using LieAlgebra = Matrix3<T>;
  /// Jacobian of the action with respect to the transform (2x3).
  using ActionJacobian = Eigen::Matrix<T, 2, 3>;

  /// The identity transform.
  SE2() : t_(Vector2<T>::Zero()) {}

  /// From a rotation and a translation (m). Rejects NaN/Inf in t.
  SE2(const SO2<T>& rotation, const Vector2<T>& translation)
      : rotation_(rotation), t_(translation) {
    ROVE_CHECK_FINITE(translation);
  }

  /// From x, y (m) and heading theta (rad). Rejects NaN/Inf.
  SE2(T x, T y, T theta) : SE2(SO2<T>::from_angle(theta), Vector2<T>(x, y)) {}

  /// From a 3x3 homogeneous matrix [[R, t]; [0 0 1]]. R is checked as in
  /// SO2(const Matrix2&); the last row must be [0 0 1] within
  /// kUnitTolerance<T>. Rejects NaN/Inf.
  explicit SE2(const Matrix3<T>& M)
      : SE2(SO2<T>(Matrix2<T>(M.template topLeftCorner<2, 2>())),
            Vector2<T>(M.template topRightCorner<2, 1>())) {
    const T err =
        (M.template bottomRows<1>() - Eigen::Matrix<T, 1, 3>(0, 0, 1)).cwiseAbs().maxCoeff();
    ROVE_CHECK_MSG(err <= kUnitTolerance<T>,
                   "last row of a homogeneous transform must be [0 0 1] (max deviation {})", err);
  }

  /// The identity transform.
  static SE2 identity() { return SE2(); }

  /// Exponential map (Eq. 156): R = R(θ), t = V(θ)·ρ with
  /// V(θ) = (sin θ/θ)·I + ((1 − cos θ)/θ)·[1]× (Eq. 158). If J_r is given it
  /// receives Jr(ξ) (Eq. 163). Rejects (InvalidArgument) NaN/Inf.
  static SE2 exp(const Tangent& xi, Jacobian* J_r = nullptr) {
    ROVE_CHECK_FINITE(xi);
    const T theta = xi(2);
    const auto k = detail::rotation_coefficients(theta);
    const T a = k.sinc;                    // sin θ / θ
    const T b = theta * k.one_minus_cos;   // (1 − cos θ) / θ
    const Vector2<T> t(a * xi(0) - b * xi(1), b * xi(0) + a * xi(1));
    if (J_r) *J_r = right_jacobian(xi);
    return SE2(SO2<T>(std::cos(theta), std::sin(theta), typename SO2<T>::Unchecked{}), t,
               Unchecked{});
  }

  /// Logarithmic map (Eq. 157): θ ∈ (−π, π], ρ = V(θ)⁻¹·t. If J_r_inv is
  /// given it receives Jr⁻¹(ξ), the Jacobian of log(X) for a right
  /// perturbation of X.
  Tangent log(Jacobian* J_r_inv = nullptr) const {
    const T c = rotation_.c_;
    const T s = rotation_.s_;
    const T theta = rotation_.angle();
    // V⁻¹ = [[h, θ/2]; [−θ/2, h]] with h = (θ/2)·cot(θ/2). Evaluate cot(θ/2)
    // as (1 + cos θ)/sin θ or sin θ/(1 − cos θ), whichever avoids cancellation.
    T h;
    if (std::abs(theta) < detail::kTaylorThreshold<T>) {
      const T t2 = theta * theta;
      h = T(1) - t2 / T(12) - t2 * t2 / T(720) - t2 * t2 * t2 / T(30240);
    } else if (c > T(0)) {
      h = T(0.5) * theta * (T(1) + c) / s;
    } else {
      h = T(0.5) * theta * s / (T(1) - c);
    }
    const T half = T(0.5) * theta;
    const Tangent xi(h * t_.x() + half * t_.y(), -half * t_.x() + h * t_.y(), theta);
    if (J_r_inv) *J_r_inv = right_jacobian_inverse(xi);
    return xi;
  }

  /// hat (Eq. 153): ξ ↦ [[0, −θ, ρx]; [θ, 0, ρy]; [0, 0, 0]].
  static LieAlgebra hat(const Tangent& xi) {
    LieAlgebra m;
    m << T(0), -xi(2), xi(0),  //
        xi(2), T(0), xi(1),    //
        T(0), T(0), T(0);
    return m;
  }
  /// vee: inverse of hat (θ from the skew part of the top-left block; the
  /// last row is ignored).
  static Tangent vee(const LieAlgebra& M) {
    return Tangent(M(0, 2), M(1, 2), T(0.5) * (M(1, 0) - M(0, 1)));
  }

  /// Adjoint (Eq. 159): [[R, (t_y, −t_x)ᵀ]; [0, 1]], so that
  /// exp(Adj·ξ) = X·exp(ξ)·X⁻¹.
  Jacobian Adj() const {
    Jacobian A;
    A.template topLeftCorner<2, 2>() = rotation_.matrix();
    A(0, 2) = t_.y();
    A(1, 2) = -t_.x();
    A.template bottomRows<1>() << T(0), T(0), T(1);
    return A;
  }

  /// Inverse (Rᵀ, −Rᵀt) (Eq. 154). If J is given it receives
  /// d(X⁻¹)/dX = −Adj(X) (Eq. 160).
  SE2 inverse(Jacobian* J = nullptr) const {
    if (J) *J = -Adj();
    const SO2<T> r_inv = rotation_.inverse();
    return SE2(r_inv, -(r_inv * t_), Unchecked{});
  }

  /// Group product (R₁R₂, t₁ + R₁t₂) (Eq. 155). Optional Jacobians (Eqs. 161,
  /// 162): J_this = Adj(other⁻¹), J_other = I.
  SE2 compose(const SE2& other, Jacobian* J_this = nullptr, Jacobian* J_other = nullptr) const {
    if (J_this) *J_this = other.inverse().Adj();
    if (J_other) J_other->setIdentity();
    return SE2(rotation_.compose(other.rotation_), t_ + rotation_ * other.t_, Unchecked{});
  }

  /// Transforms p: R·p + t (Eq. 165). Optional Jacobians (Eqs. 166, 167):
  /// J_pose = [R, R·[1]×·p] (2x3), J_point = R.
  Point act(const Point& p, ActionJacobian* J_pose = nullptr,
            Matrix2<T>* J_point = nullptr) const {
    const Point rp = rotation_ * p;
    if (J_pose) {
      J_pose->template leftCols<2>() = rotation_.matrix();
      J_pose->col(2) = Point(-rp.y(), rp.x());
    }
    if (J_point) *J_point = rotation_.matrix();
    return rp + t_;
  }

  /// Group product (see compose()).
  SE2 operator*(const SE2& other) const { return compose(other); }
  /// In-place group product.
  SE2& operator*=(const SE2& other) { return *this = compose(other); }
  /// Transforms a point.
  Point operator*(const Point& p) const { return rotation_ * p + t_; }

  /// Right ⊕: this · exp(delta).
  SE2 oplus(const Tangent& delta) const { return compose(exp(delta)); }
  /// Right ⊖: log(other⁻¹ · this).
  Tangent ominus(const SE2& other) const { return other.inverse().compose(*this).log(); }

  /// Right Jacobian (Eq. 163):
  /// [[sin θ/θ, (1−cos θ)/θ, ρx·(θ−sin θ)/θ² − ρy·(1−cos θ)/θ²];
  ///  [(cos θ−1)/θ, sin θ/θ, ρx·(1−cos θ)/θ² + ρy·(θ−sin θ)/θ²];
  ///  [0, 0, 1]].
  static Jacobian right_jacobian(const Tangent& xi) { return jacobian_impl(xi); }
  /// Left Jacobian (Eq. 164), Jl(ξ) = Jr(−ξ).
  static Jacobian left_jacobian(const Tangent& xi) { return jacobian_impl(Tangent(-xi)); }
  /// Jr⁻¹(ξ): block inverse of Eq. 163. Precondition: |θ| < 2π.
  static Jacobian right_jacobian_inverse(const Tangent& xi) {
    return jacobian_inverse_impl(xi);
  }
  /// Jl⁻¹(ξ): block inverse of Eq. 164. Precondition: |θ| < 2π.
  static Jacobian left_jacobian_inverse(const Tangent& xi) {
    return jacobian_inverse_impl(Tangent(-xi));
  }

  /// Homogeneous 3x3 matrix [[R, t]; [0 0 1]].
  Matrix3<T> matrix() const {
    Matrix3<T> m = Matrix3<T>::Identity();
    m.template topLeftCorner<2, 2>() = rotation_.matrix();
    m.template topRightCorner<2, 1>() = t_;
    return m;
  }
  /// Rotation part.
  const SO2<T>& rotation() const { return rotation_; }
  /// Rotation matrix R.
  Matrix2<T> rotation_matrix() const { return rotation_.matrix(); }
  /// Translation t (m).
  const Vector2<T>& translation() const { return t_; }
  /// Heading θ ∈ (−π, π] (rad).
  T angle() const { return rotation_.angle(); }

  /// The same transform in scalar type U.
  template <LieScalar U>
  SE2<U> cast() const {
    return SE2<U>(rotation_.template cast<U>(), t_.template cast<U>(),
                  typename SE2<U>::Unchecked{});
  }

  /// True when rotations agree as in SO2::is_approx(tol) and translations
  /// within tol·max(1, ‖t‖).
  bool is_approx(const SE2& other, T tol = default_approx_tolerance<T>()) const {
    const T scale = std::max({T(1), t_.norm(), other.t_.norm()});
    return rotation_.is_approx(other.rotation_, tol) && (t_ - other.t_).norm() <= tol * scale;
  }

 private:
  template <LieScalar>
  friend class SE2;

  struct Unchecked {};
  SE2(const SO2<T>& rotation, const Vector2<T>& translation, Unchecked)
      : rotation_(rotation), t_(translation) {}

  // Jr(ξ) of Eq. 163; Jl(ξ) = Jr(−ξ).
  static Jacobian jacobian_impl(const Tangent& xi) {
    const T x = xi(0);
    const T y = xi(1);
    const T theta = xi(2);
    const auto k = detail::rotation_coefficients(theta);
    const T a = k.sinc;                     // sin θ/θ
    const T b = theta * k.one_minus_cos;    // (1 − cos θ)/θ
    const T c = theta * k.theta_minus_sin;  // (θ − sin θ)/θ²
    const T d = k.one_minus_cos;            // (1 − cos θ)/θ²
    Jacobian J;
    J << a, b, x * c - y * d,  //
        -b, a, x * d + y * c,  //
        T(0), T(0), T(1);
    return J;
  }

  static Jacobian jacobian_inverse_impl(const Tangent& xi) {
    ROVE_CHECK_FINITE(xi);
    ROVE_CHECK_MSG(std::abs(xi(2)) < T(2) * std::numbers::pi_v<T>,
                   "inverse SE(2) Jacobian needs |θ| < 2π, got {}", xi(2));
    const Jacobian J = jacobian_impl(xi);
    // J = [[A, v]; [0, 1]] with A = [[a, b]; [−b, a]]: J⁻¹ = [[A⁻¹, −A⁻¹v]; [0, 1]].
    const T a = J(0, 0);
    const T b = J(0, 1);
    const T det = a * a + b * b;  // = (sin(θ/2)/(θ/2))², > 0 for |θ| < 2π
    Matrix2<T> A_inv;
    A_inv << a / det, -b / det, b / det, a / det;
    Jacobian Ji = Jacobian::Identity();
    Ji.template topLeftCorner<2, 2>() = A_inv;
    Ji.template topRightCorner<2, 1>() = -A_inv * J.template topRightCorner<2, 1>();
    return Ji;
  }

  SO2<T> rotation_;
  Vector2<T> t_;
};

/// Double-precision SE2.
using SE2d = SE2<double>;
/// Single-precision SE2.
using SE2f = SE2<float>;

}  // namespace rove
