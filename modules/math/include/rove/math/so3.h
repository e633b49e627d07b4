#pragma once
/// \file
/// SO3<T>: 3D rotations as a Lie group, with exp/log, Adjoint and the
/// Jacobians of Solà, Deray, Atchuthan, "A micro Lie theory for state
/// estimation in robotics" (2018, arXiv:1812.01537); equation numbers below
/// refer to that paper.
///
/// Conventions (docs/conventions.md): tangent ω ∈ R³ is a rotation vector in
/// radians; perturbations are on the right, X ⊕ δ = X · exp(δ),
/// Y ⊖ X = log(X⁻¹ · Y); Jacobians are right Jacobians unless named "left".
///
/// Storage: a unit quaternion. It makes exp, log, the group product and SE3's
/// exp/log (which reuse the half-angle sine and cosine) the cheapest
/// representation: the product is 16 multiply-adds plus a square-root-free
/// renormalization (versus 27 for a matrix and a costly re-orthogonalization),
/// exp needs one sin/cos pair and log one atan2 with no acos/asin near 0 or π.
/// Rotating a single point costs about as much as with a matrix; callers
/// transforming many points should take matrix() once.
///
/// Near θ = π the quaternion's vector part has norm sin(θ/2) ≈ 1, so log()
/// takes the axis from it without dividing by sin θ ≈ 0. Matrices are turned
/// into quaternions with Shepperd's method (via Eigen): at large angles it
/// reads the axis from the symmetric part R + Rᵀ (largest diagonal entry),
/// never from the vanishing skew part.

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <Eigen/SVD>

#include "rove/core/check.h"
#include "rove/math/detail/lie_coefficients.h"
#include "rove/math/types.h"

namespace rove {

/// A 3D rotation R ∈ SO(3), stored as a unit quaternion. Plain value type;
/// thread-compatible (const methods may be called concurrently).
template <LieScalar T>
class SO3 {
 public:
  using Scalar = T;
  /// Degrees of freedom.
  static constexpr int kDof = 3;
  /// Rotation vector ω (axis · angle, radians).
  using Tangent = Vector3<T>;
  /// Jacobians between tangent spaces (3x3).
  using Jacobian = Matrix3<T>;
  /// Point in R³.
  using Point = Vector3<T>;
  /// Lie-algebra element (3x3 skew-symmetric matrix).
  using LieAlgebra = Matrix3<T>;
  /// Jacobian of the action with respect to the rotation (3x3).
  using ActionJacobian = Matrix3<T>;

  /// The identity rotation.
  SO3() : q_(Quaternion<T>::Identity()) {}

  /// From a unit quaternion (w, x, y, z). Rejects (InvalidArgument) NaN/Inf
  /// and any q with |‖q‖ − 1| > kUnitTolerance<T>; an accepted q is
  /// normalized exactly. Use from_unnormalized() for arbitrary non-zero q.
  explicit SO3(const Quaternion<T>& q) : q_(q) {
    ROVE_CHECK_FINITE(q.coeffs());
    const T norm = q.norm();
    ROVE_CHECK_MSG(std::abs(norm - T(1)) <= kUnitTolerance<T>,
                   "quaternion norm {} differs from 1 by more than {}; use "
                   "SO3::from_unnormalized() to normalize on purpose",
                   norm, kUnitTolerance<T>);
    q_.coeffs() /= norm;
  }

  /// From a rotation matrix. Rejects (InvalidArgument) NaN/Inf, matrices with
  /// an entry of RᵀR − I larger than kUnitTolerance<T>, and det(R) < 0.
  /// Use from_matrix_orthonormalized() for approximate rotation matrices.
  explicit SO3(const Matrix3<T>& R) {
    ROVE_CHECK_FINITE(R);
    const T err = (R.transpose() * R - Matrix3<T>::Identity()).cwiseAbs().maxCoeff();
    ROVE_CHECK_MSG(err <= kUnitTolerance<T>,
                   "matrix is not orthonormal: max |RᵀR − I| = {} > {}; use "
                   "SO3::from_matrix_orthonormalized()",
                   err, kUnitTolerance<T>);
    ROVE_CHECK_MSG(R.determinant() > T(0), "matrix is a reflection (det < 0)");
    q_ = Quaternion<T>(R);
    q_.normalize();
  }

  /// From any finite, non-zero quaternion, divided by its norm. Rejects
  /// (InvalidArgument) NaN/Inf and a norm below the smallest normal number.
  static SO3 from_unnormalized(const Quaternion<T>& q) {
    ROVE_CHECK_FINITE(q.coeffs());
    const T norm = q.norm();
    ROVE_CHECK_MSG(norm > std::numeric_limits<T>::min(),
                   "cannot normalize a zero quaternion");
    return SO3(Quaternion<T>(q.coeffs() / norm), Unchecked{});
  }

  /// The rotation nearest (Frobenius norm) to M: U·diag(1, 1, det(UVᵀ))·Vᵀ
  /// from M's SVD. Rejects (InvalidArgument) NaN/Inf and det(M) ≤ 0
  /// (a reflection or a singular matrix is not an approximate rotation).
  static SO3 from_matrix_orthonormalized(const Matrix3<T>& M) {
    ROVE_CHECK_FINITE(M);
    ROVE_CHECK_MSG(M.determinant() > T(0),
                   "matrix with det {} ≤ 0 is not an approximate rotation", M.determinant());
    const Eigen::JacobiSVD<Matrix3<T>> svd(M, Eigen::ComputeFullU | Eigen::ComputeFullV);
    Matrix3<T> D = Matrix3<T>::Identity();
    D(2, 2) = (svd.matrixU() * svd.matrixV().transpose()).determinant() < T(0) ? T(-1) : T(1);
    const Matrix3<T> R = svd.matrixU() * D * svd.matrixV().transpose();
    Quaternion<T> q(R);
    q.normalize();
    return SO3(q, Unchecked{});
  }

  /// The identity rotation.
  static SO3 identity() { return SO3(); }

  /// Rotation of `angle` radians about the x axis.
  static SO3 rot_x(T angle) { return exp(Tangent(angle, T(0), T(0))); }
  /// Rotation of `angle` radians about the y axis.
  static SO3 rot_y(T angle) { return exp(Tangent(T(0), angle, T(0))); }
  /// Rotation of `angle` radians about the z axis.
  static SO3 rot_z(T angle) { return exp(Tangent(T(0), T(0), angle)); }

  /// Exponential map (Eq. 132): the rotation of |ω| radians about ω/|ω|.
  /// If J_r is given, it receives the right Jacobian Jr(ω) (Eq. 143).
  /// Rejects (InvalidArgument) NaN/Inf in ω.
  static SO3 exp(const Tangent& omega, Jacobian* J_r = nullptr) {
    ROVE_CHECK_FINITE(omega);
    const T theta2 = omega.squaredNorm();
    const T theta = std::sqrt(theta2);
    T w;
    T k;  // sin(θ/2) / θ
    if (theta < detail::kTaylorThreshold<T>) {
      const T t4 = theta2 * theta2;
      k = T(0.5) - theta2 / T(48) + t4 / T(3840) - t4 * theta2 / T(645120);
      w = std::cos(theta / T(2));
    } else {
      const T half = theta / T(2);
      w = std::cos(half);
      k = std::sin(half) / theta;
    }
    if (J_r) *J_r = right_jacobian(omega);
    return SO3(Quaternion<T>(w, k * omega.x(), k * omega.y(), k * omega.z()), Unchecked{});
  }

  /// Logarithmic map (Eq. 133): the rotation vector ω with |ω| ∈ [0, π].
  /// If J_r_inv is given, it receives Jr⁻¹(ω) (Eq. 144), the Jacobian of
  /// log(X) with respect to a right perturbation of X.
  Tangent log(Jacobian* J_r_inv = nullptr) const {
    const Tangent omega = log_from_quaternion(q_);
    if (J_r_inv) *J_r_inv = right_jacobian_inverse(omega);
    return omega;
  }

  /// hat: ω ↦ [ω]× (skew-symmetric, [ω]× p = ω × p).
  static LieAlgebra hat(const Tangent& omega) { return detail::skew(omega); }

  /// vee: inverse of hat. Reads the skew-symmetric part ½(M − Mᵀ) of M.
  static Tangent vee(const LieAlgebra& M) {
    return Tangent(M(2, 1) - M(1, 2), M(0, 2) - M(2, 0), M(1, 0) - M(0, 1)) * T(0.5);
  }

  /// Adjoint matrix Adj(R) = R (Eq. 139): exp(Adj·ω) = R·exp(ω)·R⁻¹.
  Jacobian Adj() const { return matrix(); }

  /// Inverse rotation Rᵀ (Eq. 140, conjugate quaternion). If J is given it
  /// receives d(R⁻¹)/dR = −Adj(R) = −R.
  SO3 inverse(Jacobian* J = nullptr) const {
    if (J) *J = -matrix();
    return SO3(q_.conjugate(), Unchecked{});
  }

  /// Group product this · other (Eq. 141), renormalized. Optional Jacobians
  /// (Eq. 142): J_this = d(R·S)/dR = Adj(S⁻¹) = Sᵀ, J_other = d(R·S)/dS = I.
  SO3 compose(const SO3& other, Jacobian* J_this = nullptr, Jacobian* J_other = nullptr) const {
    if (J_this) *J_this = other.matrix().transpose();
    if (J_other) J_other->setIdentity();
    Quaternion<T> q = q_ * other.q_;
    detail::renormalize_near_unit(q);
    return SO3(q, Unchecked{});
  }

  /// Rotates point p: R·p (Eq. 136). Optional Jacobians (Eqs. 150, 151):
  /// J_rotation = d(R·p)/dR = −R·[p]×, J_point = d(R·p)/dp = R.
  Point act(const Point& p, ActionJacobian* J_rotation = nullptr,
            Matrix3<T>* J_point = nullptr) const {
    if (J_rotation || J_point) {
      const Matrix3<T> R = matrix();
      if (J_rotation) *J_rotation = -R * detail::skew(p);
      if (J_point) *J_point = R;
    }
    return q_ * p;
  }

  /// Group product (see compose()).
  SO3 operator*(const SO3& other) const { return compose(other); }
  /// In-place group product: *this = *this · other.
  SO3& operator*=(const SO3& other) { return *this = compose(other); }
  /// Rotation of a point (see act()).
  Point operator*(const Point& p) const { return q_ * p; }

  /// Right ⊕ (Eq. 25): this · exp(delta).
  SO3 oplus(const Tangent& delta) const { return compose(exp(delta)); }
  /// Right ⊖ (Eq. 26): log(other⁻¹ · this), the tangent at `other` taking it
  /// to *this.
  Tangent ominus(const SO3& other) const { return other.inverse().compose(*this).log(); }

  /// Right Jacobian Jr(ω) = I − (1−cos θ)/θ² [ω]× + (θ−sin θ)/θ³ [ω]×²
  /// (Eq. 143): exp(ω + δ) ≈ exp(ω)·exp(Jr(ω)·δ).
  static Jacobian right_jacobian(const Tangent& omega) {
    return jacobian_impl(omega, T(-1));
  }
  /// Left Jacobian Jl(ω) = Jr(−ω) = I + (1−cos θ)/θ² [ω]× + (θ−sin θ)/θ³ [ω]×²
  /// (Eq. 145): exp(ω + δ) ≈ exp(Jl(ω)·δ)·exp(ω).
  static Jacobian left_jacobian(const Tangent& omega) { return jacobian_impl(omega, T(1)); }
  /// Jr⁻¹(ω) = I + ½[ω]× + (1/θ² − (1+cos θ)/(2θ sin θ)) [ω]×² (Eq. 144).
  /// Precondition: |ω| < 2π (Jr is singular at 2π).
  static Jacobian right_jacobian_inverse(const Tangent& omega) {
    return jacobian_inverse_impl(omega, T(1));
  }
  /// Jl⁻¹(ω) = Jr⁻¹(−ω) (Eq. 146). Precondition: |ω| < 2π.
  static Jacobian left_jacobian_inverse(const Tangent& omega) {
    return jacobian_inverse_impl(omega, T(-1));
  }

  /// Rotation matrix R.
  Matrix3<T> matrix() const { return q_.toRotationMatrix(); }
  /// Unit quaternion (w ≥ 0 not guaranteed; q and −q are the same rotation).
  const Quaternion<T>& quaternion() const { return q_; }

  /// The same rotation in scalar type U (renormalized in U).
  template <LieScalar U>
  SO3<U> cast() const {
    Quaternion<U> q = q_.template cast<U>();
    q.normalize();
    return SO3<U>(q, typename SO3<U>::Unchecked{});
  }

  /// True when the rotations agree within `tol`, measured as the chordal
  /// quaternion distance min(‖q₁ − q₂‖, ‖q₁ + q₂‖) (≈ half the angle between
  /// them, radians, for small differences).
  bool is_approx(const SO3& other, T tol = default_approx_tolerance<T>()) const {
    const T d_minus = (q_.coeffs() - other.q_.coeffs()).norm();
    const T d_plus = (q_.coeffs() + other.q_.coeffs()).norm();
    return std::min(d_minus, d_plus) <= tol;
  }

 private:
  template <LieScalar>
  friend class SO3;
  template <LieScalar>
  friend class SE3;

  struct Unchecked {};
  SO3(const Quaternion<T>& unit_q, Unchecked) : q_(unit_q) {}

  static Tangent log_from_quaternion(const Quaternion<T>& q_in) {
    // Take the representative with w ≥ 0 so that θ = 2·atan2(n, w) ∈ [0, π].
    const T sign = q_in.w() < T(0) ? T(-1) : T(1);
    const T w = sign * q_in.w();
    const Vector3<T> v = sign * q_in.vec();
    const T n2 = v.squaredNorm();
    const T n = std::sqrt(n2);
    T factor;  // θ / n
    if (n < detail::kTaylorThreshold<T> * T(0.5)) {
      // 2·atan(r)/n with r = n/w: 2/w·(1 − r²/3 + r⁴/5 − r⁶/7). Here w ≈ 1.
      const T r2 = n2 / (w * w);
      factor = T(2) / w * (T(1) - r2 / T(3) + r2 * r2 / T(5) - r2 * r2 * r2 / T(7));
    } else {
      factor = T(2) * std::atan2(n, w) / n;
    }
    return factor * v;
  }

  // sign = −1: Jr; sign = +1: Jl.
  static Jacobian jacobian_impl(const Tangent& omega, T sign) {
    const T theta = omega.norm();
    const auto k = detail::rotation_coefficients(theta);
    const Matrix3<T> W = detail::skew(omega);
    return Matrix3<T>::Identity() + (sign * k.one_minus_cos) * W + k.theta_minus_sin * (W * W);
  }

  // sign = +1: Jr⁻¹; sign = −1: Jl⁻¹.
  static Jacobian jacobian_inverse_impl(const Tangent& omega, T sign) {
    ROVE_CHECK_FINITE(omega);
    const T theta = omega.norm();
    ROVE_CHECK_MSG(theta < T(2) * std::numbers::pi_v<T>,
                   "inverse SO(3) Jacobian needs |ω| < 2π, got {}", theta);
    const T e = detail::inverse_jacobian_coefficient(theta);
    const Matrix3<T> W = detail::skew(omega);
    return Matrix3<T>::Identity() + (sign * T(0.5)) * W + e * (W * W);
  }

  Quaternion<T> q_;
};

/// Double-precision SO3.
using SO3d = SO3<double>;
/// Single-precision SO3.
using SO3f = SO3<float>;

}  // namespace rove
