#pragma once
/// \file
/// SE3<T>: 3D rigid transforms as a Lie group, with exp/log, Adjoint and the
/// Jacobians of Solà, Deray, Atchuthan, "A micro Lie theory for state
/// estimation in robotics" (2018, arXiv:1812.01537), Appendix D; equation
/// numbers below refer to that paper.
///
/// Conventions (docs/conventions.md): tangent ξ = [ρ; ω] with translation
/// first, ρ = [rho_x, rho_y, rho_z] (meters), ω = [w_x, w_y, w_z] (radians);
/// perturbations on the right, X ⊕ δ = X · exp(δ), Y ⊖ X = log(X⁻¹ · Y).
/// An SE3 T_a_b maps points in frame b into frame a: p_a = T_a_b · p_b.
///
/// Storage: SO3 (unit quaternion, see so3.h for why) and a translation.
/// exp() and log() share one half-angle sin/cos (or one atan2) between the
/// rotation and the translation map V(ω) = Jl(ω).

#include <algorithm>
#include <cmath>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "rove/core/check.h"
#include "rove/math/detail/lie_coefficients.h"
#include "rove/math/so3.h"
#include "rove/math/types.h"

namespace rove {

/// A rigid transform (R, t) ∈ SE(3): p ↦ R·p + t. Plain value type;
/// thread-compatible.
template <LieScalar T>
class SE3 {
 public:
  using Scalar = T;
  /// Degrees of freedom.
  static constexpr int kDof = 6;
  /// Tangent [ρ; ω]: translation part (m) first, then rotation vector (rad).
  using Tangent = Vector6<T>;
  /// Jacobians between tangent spaces (6x6, same ordering as Tangent).
  using Jacobian = Matrix6<T>;
  /// Point in R³.
  using Point = Vector3<T>;
  /// Lie-algebra element (4x4, [[ω]×, ρ; 0, 0]).
  using LieAlgebra = Matrix4<T>;
  /// Jacobian of the action with respect to the transform (3x6).
  using ActionJacobian = Eigen::Matrix<T, 3, 6>;

  /// The identity transform.
  SE3() : t_(Vector3<T>::Zero()) {}

  /// From a rotation and a translation (m). Rejects NaN/Inf in t.
  SE3(const SO3<T>& rotation, const Vector3<T>& translation)
      : rotation_(rotation), t_(translation) {
    ROVE_CHECK_FINITE(translation);
  }

  /// From a unit quaternion (checked as in SO3(const Quaternion&)) and a
  /// translation (m). Rejects NaN/Inf.
  SE3(const Quaternion<T>& q, const Vector3<T>& translation)
      : SE3(SO3<T>(q), translation) {}

  /// From a rotation matrix (checked as in SO3(const Matrix3&)) and a
  /// translation (m). Rejects NaN/Inf.
  SE3(const Matrix3<T>& R, const Vector3<T>& translation) : SE3(SO3<T>(R), translation) {}

  /// From a 4x4 homogeneous matrix [[R, t]; [0 0 0 1]]. R is checked as in
  /// SO3(const Matrix3&); the last row must be [0 0 0 1] within
  /// kUnitTolerance<T>. Rejects NaN/Inf.
  explicit SE3(const Matrix4<T>& M)
      : SE3(SO3<T>(Matrix3<T>(M.template topLeftCorner<3, 3>())),
            Vector3<T>(M.template topRightCorner<3, 1>())) {
    const T err = (M.template bottomRows<1>() - Eigen::Matrix<T, 1, 4>(0, 0, 0, 1))
                      .cwiseAbs()
                      .maxCoeff();
    ROVE_CHECK_MSG(err <= kUnitTolerance<T>, "last row of a homogeneous transform must be "
                                             "[0 0 0 1] (max deviation {})",
                   err);
  }

  /// The identity transform.
  static SE3 identity() { return SE3(); }

  /// Exponential map (Eq. 172): R = exp(ω), t = V(ω)·ρ with V(ω) = Jl(ω) of
  /// SO(3). If J_r is given, it receives the right Jacobian Jr(ξ)
  /// (Eqs. 179, 180). Rejects (InvalidArgument) NaN/Inf in ξ.
  static SE3 exp(const Tangent& xi, Jacobian* J_r = nullptr) {
    ROVE_CHECK_FINITE(xi);
    const Vector3<T> rho = xi.template head<3>();
    const Vector3<T> omega = xi.template tail<3>();
    const T theta2 = omega.squaredNorm();
    const T theta = std::sqrt(theta2);
    T w, k, b, c;  // cos(θ/2), sin(θ/2)/θ, (1−cos θ)/θ², (θ−sin θ)/θ³
    if (theta < detail::kTaylorThreshold<T>) {
      const T t4 = theta2 * theta2;
      const T t6 = t4 * theta2;
      w = std::cos(theta / T(2));
      k = T(0.5) - theta2 / T(48) + t4 / T(3840) - t6 / T(645120);
      b = T(0.5) - theta2 / T(24) + t4 / T(720) - t6 / T(40320);
      c = T(1) / T(6) - theta2 / T(120) + t4 / T(5040) - t6 / T(362880);
    } else {
      const T half = theta / T(2);
      const T sh = std::sin(half);
      const T inv_theta = T(1) / theta;  // one division instead of three
      w = std::cos(half);
      k = sh * inv_theta;
      // 1 − cos θ = 2 sin²(θ/2) and sin θ = 2 sin(θ/2) cos(θ/2): no cancellation in b.
      b = T(2) * k * k;
      c = (theta - T(2) * sh * w) * (inv_theta * inv_theta * inv_theta);
    }
    const Vector3<T> w_x_rho = omega.cross(rho);
    const Vector3<T> t = rho + b * w_x_rho + c * omega.cross(w_x_rho);
    if (J_r) *J_r = right_jacobian(xi);
    return SE3(SO3<T>(Quaternion<T>(w, k * omega.x(), k * omega.y(), k * omega.z()),
                      typename SO3<T>::Unchecked{}),
               t, Unchecked{});
  }

  /// Logarithmic map (Eq. 173): ω = log(R) with |ω| ∈ [0, π], ρ = V(ω)⁻¹·t.
  /// If J_r_inv is given, it receives Jr⁻¹(ξ) (Eqs. 179, 180 and the note
  /// after them), the Jacobian of log(X) for a right perturbation of X.
  Tangent log(Jacobian* J_r_inv = nullptr) const {
    const Quaternion<T>& q = rotation_.quaternion();
    const T sign = q.w() < T(0) ? T(-1) : T(1);
    const T w = sign * q.w();
    const Vector3<T> v = sign * q.vec();
    const T n2 = v.squaredNorm();
    const T n = std::sqrt(n2);
    T theta;
    T factor;  // θ / n
    if (n < detail::kTaylorThreshold<T> * T(0.5)) {
      const T r2 = n2 / (w * w);
      factor = T(2) / w * (T(1) - r2 / T(3) + r2 * r2 / T(5) - r2 * r2 * r2 / T(7));
      theta = factor * n;
    } else {
      theta = T(2) * std::atan2(n, w);
      factor = theta / n;
    }
    const Vector3<T> omega = factor * v;
    // V⁻¹ = Jl⁻¹(ω) = I − ½[ω]× + e [ω]×² (Eq. 146), e from the half angle.
    const T e = detail::inverse_jacobian_coefficient_from_half_angle(theta, w, n);
    const Vector3<T> w_x_t = omega.cross(t_);
    Tangent xi;
    xi.template head<3>() = t_ - T(0.5) * w_x_t + e * omega.cross(w_x_t);
    xi.template tail<3>() = omega;
    if (J_r_inv) *J_r_inv = right_jacobian_inverse(xi);
    return xi;
  }

  /// hat (Eq. 169): ξ ↦ [[ω]×, ρ; 0, 0].
  static LieAlgebra hat(const Tangent& xi) {
    LieAlgebra m = LieAlgebra::Zero();
    m.template topLeftCorner<3, 3>() = detail::skew<T>(xi.template tail<3>());
    m.template topRightCorner<3, 1>() = xi.template head<3>();
    return m;
  }

  /// vee: inverse of hat. Reads ρ from the last column and ω from the skew
  /// part of the top-left block; the last row is ignored.
  static Tangent vee(const LieAlgebra& M) {
    Tangent xi;
    xi.template head<3>() = M.template topRightCorner<3, 1>();
    xi.template tail<3>() = SO3<T>::vee(M.template topLeftCorner<3, 3>());
    return xi;
  }

  /// Adjoint (Eq. 175): [[R, [t]×R]; [0, R]], so that
  /// exp(Adj·ξ) = X·exp(ξ)·X⁻¹.
  Jacobian Adj() const {
    const Matrix3<T> R = rotation_.matrix();
    Jacobian A;
    A.template topLeftCorner<3, 3>() = R;
    A.template topRightCorner<3, 3>() = detail::skew(t_) * R;
    A.template bottomLeftCorner<3, 3>().setZero();
    A.template bottomRightCorner<3, 3>() = R;
    return A;
  }

  /// Inverse (Rᵀ, −Rᵀt) (Eq. 170). If J is given it receives
  /// d(X⁻¹)/dX = −Adj(X) (Eq. 176).
  SE3 inverse(Jacobian* J = nullptr) const {
    if (J) *J = -Adj();
    const SO3<T> r_inv = rotation_.inverse();
    return SE3(r_inv, -(r_inv * t_), Unchecked{});
  }

  /// Group product this · other = (R₁R₂, t₁ + R₁t₂) (Eq. 171). Optional
  /// Jacobians (Eqs. 177, 178): J_this = Adj(other⁻¹), J_other = I.
  SE3 compose(const SE3& other, Jacobian* J_this = nullptr, Jacobian* J_other = nullptr) const {
    if (J_this) *J_this = other.inverse().Adj();
    if (J_other) J_other->setIdentity();
    return SE3(rotation_.compose(other.rotation_), t_ + rotation_ * other.t_, Unchecked{});
  }

  /// Transforms point p: R·p + t (Eq. 181). Optional Jacobians (Eqs. 182,
  /// 183): J_pose = d(X·p)/dX = [R, −R[p]×] (3x6), J_point = d(X·p)/dp = R.
  Point act(const Point& p, ActionJacobian* J_pose = nullptr,
            Matrix3<T>* J_point = nullptr) const {
    if (J_pose || J_point) {
      const Matrix3<T> R = rotation_.matrix();
      if (J_pose) {
        J_pose->template leftCols<3>() = R;
        J_pose->template rightCols<3>() = -R * detail::skew(p);
      }
      if (J_point) *J_point = R;
    }
    return rotation_ * p + t_;
  }

  /// Group product (see compose()).
  SE3 operator*(const SE3& other) const { return compose(other); }
  /// In-place group product: *this = *this · other.
  SE3& operator*=(const SE3& other) { return *this = compose(other); }
  /// Transforms a point (see act()).
  Point operator*(const Point& p) const { return rotation_ * p + t_; }

  /// Right ⊕ (Eq. 25): this · exp(delta).
  SE3 oplus(const Tangent& delta) const { return compose(exp(delta)); }
  /// Right ⊖ (Eq. 26): log(other⁻¹ · this).
  Tangent ominus(const SE3& other) const { return other.inverse().compose(*this).log(); }

  /// Right Jacobian Jr(ξ) = [[Jr(ω), Q(−ρ, −ω)]; [0, Jr(ω)]] (Eqs. 179, 180
  /// with Jr(ξ) = Jl(−ξ)): exp(ξ + δ) ≈ exp(ξ)·exp(Jr(ξ)·δ).
  static Jacobian right_jacobian(const Tangent& xi) {
    return left_jacobian(Tangent(-xi));
  }
  /// Left Jacobian Jl(ξ) = [[Jl(ω), Q(ρ, ω)]; [0, Jl(ω)]] (Eqs. 179, 180):
  /// exp(ξ + δ) ≈ exp(Jl(ξ)·δ)·exp(ξ).
  static Jacobian left_jacobian(const Tangent& xi) {
    const Vector3<T> rho = xi.template head<3>();
    const Vector3<T> omega = xi.template tail<3>();
    const Matrix3<T> Jl = SO3<T>::left_jacobian(omega);
    Jacobian J;
    J.template topLeftCorner<3, 3>() = Jl;
    J.template topRightCorner<3, 3>() = q_block(rho, omega);
    J.template bottomLeftCorner<3, 3>().setZero();
    J.template bottomRightCorner<3, 3>() = Jl;
    return J;
  }
  /// Jr⁻¹(ξ) = [[Jr⁻¹, −Jr⁻¹·Q(−ρ, −ω)·Jr⁻¹]; [0, Jr⁻¹]] with Jr⁻¹ of SO(3)
  /// at ω (note after Eq. 180). Precondition: |ω| < 2π.
  static Jacobian right_jacobian_inverse(const Tangent& xi) {
    return left_jacobian_inverse(Tangent(-xi));
  }
  /// Jl⁻¹(ξ) = [[Jl⁻¹, −Jl⁻¹·Q(ρ, ω)·Jl⁻¹]; [0, Jl⁻¹]]. Precondition: |ω| < 2π.
  static Jacobian left_jacobian_inverse(const Tangent& xi) {
    const Vector3<T> rho = xi.template head<3>();
    const Vector3<T> omega = xi.template tail<3>();
    const Matrix3<T> Jl_inv = SO3<T>::left_jacobian_inverse(omega);
    Jacobian J;
    J.template topLeftCorner<3, 3>() = Jl_inv;
    J.template topRightCorner<3, 3>() = -Jl_inv * q_block(rho, omega) * Jl_inv;
    J.template bottomLeftCorner<3, 3>().setZero();
    J.template bottomRightCorner<3, 3>() = Jl_inv;
    return J;
  }

  /// Homogeneous 4x4 matrix [[R, t]; [0 0 0 1]].
  Matrix4<T> matrix() const {
    Matrix4<T> m = Matrix4<T>::Identity();
    m.template topLeftCorner<3, 3>() = rotation_.matrix();
    m.template topRightCorner<3, 1>() = t_;
    return m;
  }
  /// Rotation part.
  const SO3<T>& rotation() const { return rotation_; }
  /// Rotation matrix R.
  Matrix3<T> rotation_matrix() const { return rotation_.matrix(); }
  /// Unit quaternion of the rotation part.
  const Quaternion<T>& quaternion() const { return rotation_.quaternion(); }
  /// Translation t (m).
  const Vector3<T>& translation() const { return t_; }

  /// The same transform in scalar type U.
  template <LieScalar U>
  SE3<U> cast() const {
    return SE3<U>(rotation_.template cast<U>(), t_.template cast<U>(),
                  typename SE3<U>::Unchecked{});
  }

  /// True when rotations agree as in SO3::is_approx(tol) and translations
  /// within tol·max(1, ‖t‖) (absolute near the origin, relative far away).
  bool is_approx(const SE3& other, T tol = default_approx_tolerance<T>()) const {
    const T scale = std::max({T(1), t_.norm(), other.t_.norm()});
    return rotation_.is_approx(other.rotation_, tol) && (t_ - other.t_).norm() <= tol * scale;
  }

 private:
  template <LieScalar>
  friend class SE3;

  struct Unchecked {};
  SE3(const SO3<T>& rotation, const Vector3<T>& translation, Unchecked)
      : rotation_(rotation), t_(translation) {}

  // Q(ρ, θ) of Eq. 180 (Barfoot & Furgale 2014, Eq. 102), the coupling block
  // of the SE(3) left Jacobian.
  static Matrix3<T> q_block(const Vector3<T>& rho, const Vector3<T>& omega) {
    const T theta = omega.norm();
    const auto k = detail::rotation_coefficients(theta);
    const auto q = detail::se3_q_coefficients(theta);
    const Matrix3<T> P = detail::skew(rho);
    const Matrix3<T> W = detail::skew(omega);
    const Matrix3<T> WP = W * P;
    const Matrix3<T> PW = P * W;
    const Matrix3<T> WPW = WP * W;
    return T(0.5) * P + k.theta_minus_sin * (WP + PW + WPW) +
           q.c4 * (W * WP + PW * W - T(3) * WPW) + q.c5 * (WPW * W + W * WPW);
  }

  SO3<T> rotation_;
  Vector3<T> t_;
};

/// Double-precision SE3.
using SE3d = SE3<double>;
/// Single-precision SE3.
using SE3f = SE3<float>;

}  // namespace rove
