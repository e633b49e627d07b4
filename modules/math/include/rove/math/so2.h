#pragma once
/// \file
/// SO2<T>: planar rotations as a Lie group, following Solà, Deray,
/// Atchuthan, "A micro Lie theory for state estimation in robotics" (2018,
/// arXiv:1812.01537), Appendix A; equation numbers below refer to that paper.
///
/// Tangent: Eigen 1-vector [θ] (radians), so that generic code treats all
/// groups alike; from_angle() / angle() are the scalar shortcuts. SO(2) is
/// commutative, so Adj, Jr, Jl and their inverses are all 1 (Eqs. 123, 126).
/// Storage: the unit complex number (cos θ, sin θ), renormalized after
/// products.

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include <Eigen/Core>

#include "rove/core/check.h"
#include "rove/math/detail/lie_coefficients.h"
#include "rove/math/types.h"

namespace rove {

/// A planar rotation R(θ) ∈ SO(2). Plain value type; thread-compatible.
template <LieScalar T>
class SO2 {
 public:
  using Scalar = T;
  /// Degrees of freedom.
  static constexpr int kDof = 1;
  /// Tangent [θ] (radians).
  using Tangent = VectorN<T, 1>;
  /// Jacobians between tangent spaces (1x1).
  using Jacobian = Eigen::Matrix<T, 1, 1>;
  /// Point in R².
  using Point = Vector2<T>;
  /// Lie-algebra element (2x2 skew-symmetric).
  using LieAlgebra = Matrix2<T>;
  /// Jacobian of the action with respect to the rotation (2x1).
  using ActionJacobian = Eigen::Matrix<T, 2, 1>;

  /// The identity rotation.
  SO2() : c_(T(1)), s_(T(0)) {}

  /// From a rotation matrix. Rejects (InvalidArgument) NaN/Inf, an entry of
  /// RᵀR − I larger than kUnitTolerance<T>, and det(R) < 0.
  explicit SO2(const Matrix2<T>& R) {
    ROVE_CHECK_FINITE(R);
    const T err = (R.transpose() * R - Matrix2<T>::Identity()).cwiseAbs().maxCoeff();
    ROVE_CHECK_MSG(err <= kUnitTolerance<T>, "matrix is not orthonormal: max |RᵀR − I| = {} > {}",
                   err, kUnitTolerance<T>);
    ROVE_CHECK_MSG(R.determinant() > T(0), "matrix is a reflection (det < 0)");
    // Average the two copies of cos and sin, then normalize.
    set_normalized(R(0, 0) + R(1, 1), R(1, 0) - R(0, 1));
  }

  /// Rotation by `theta` radians (any value; wrapped by log()). Rejects NaN/Inf.
  static SO2 from_angle(T theta) {
    ROVE_CHECK_FINITE(theta);
    return SO2(std::cos(theta), std::sin(theta), Unchecked{});
  }

  /// From a unit complex number re + i·im = cos θ + i·sin θ. Rejects NaN/Inf
  /// and |‖(re, im)‖ − 1| > kUnitTolerance<T>; normalizes an accepted input.
  static SO2 from_complex(T re, T im) {
    ROVE_CHECK_FINITE(Vector2<T>(re, im));
    const T norm = std::hypot(re, im);
    ROVE_CHECK_MSG(std::abs(norm - T(1)) <= kUnitTolerance<T>,
                   "complex number norm {} differs from 1 by more than {}", norm,
                   kUnitTolerance<T>);
    return SO2(re / norm, im / norm, Unchecked{});
  }

  /// The identity rotation.
  static SO2 identity() { return SO2(); }

  /// Exponential map (Eq. 114): R(θ). If J_r is given it receives Jr = 1
  /// (Eq. 126). Rejects NaN/Inf.
  static SO2 exp(const Tangent& theta, Jacobian* J_r = nullptr) {
    if (J_r) J_r->setOnes();
    return from_angle(theta(0));
  }

  /// Logarithmic map (Eq. 115): [θ] with θ ∈ (−π, π]. If J_r_inv is given it
  /// receives Jr⁻¹ = 1 (Eq. 126).
  Tangent log(Jacobian* J_r_inv = nullptr) const {
    if (J_r_inv) J_r_inv->setOnes();
    return Tangent(angle());
  }

  /// Rotation angle θ ∈ (−π, π] (radians).
  T angle() const {
    const T a = std::atan2(s_, c_);
    return a == -std::numbers::pi_v<T> ? std::numbers::pi_v<T> : a;  // sin = −0 at a half turn
  }

  /// hat (Eq. 112): [θ] ↦ [[0, −θ]; [θ, 0]].
  static LieAlgebra hat(const Tangent& theta) {
    LieAlgebra m;
    m << T(0), -theta(0), theta(0), T(0);
    return m;
  }
  /// vee (Eq. 113): inverse of hat, reading the skew part ½(M(1,0) − M(0,1)).
  static Tangent vee(const LieAlgebra& M) { return Tangent(T(0.5) * (M(1, 0) - M(0, 1))); }

  /// Adjoint Adj = 1 (Eq. 123).
  Jacobian Adj() const { return Jacobian::Ones(); }

  /// Inverse rotation R(−θ) (Eq. 118). If J is given it receives
  /// d(R⁻¹)/dR = −1 (Eq. 124).
  SO2 inverse(Jacobian* J = nullptr) const {
    if (J) J->setConstant(T(-1));
    return SO2(c_, -s_, Unchecked{});
  }

  /// Group product R(θ₁ + θ₂) (Eq. 125), renormalized. Optional Jacobians:
  /// J_this = Adj(other⁻¹) = 1, J_other = 1.
  SO2 compose(const SO2& other, Jacobian* J_this = nullptr, Jacobian* J_other = nullptr) const {
    if (J_this) J_this->setOnes();
    if (J_other) J_other->setOnes();
    T c = c_ * other.c_ - s_ * other.s_;
    T s = s_ * other.c_ + c_ * other.s_;
    const T k = (T(3) - (c * c + s * s)) * T(0.5);  // first-order renormalization
    return SO2(c * k, s * k, Unchecked{});
  }

  /// Rotates p (Eq. 129). Optional Jacobians (Eq. 130):
  /// J_rotation = R·[1]×·p (2x1), J_point = R.
  Point act(const Point& p, ActionJacobian* J_rotation = nullptr,
            Matrix2<T>* J_point = nullptr) const {
    const Point rp = rotate(p);
    if (J_rotation) *J_rotation = Point(-rp.y(), rp.x());  // R·[1]×·p = [1]×·R·p
    if (J_point) *J_point = matrix();
    return rp;
  }

  /// Group product (see compose()).
  SO2 operator*(const SO2& other) const { return compose(other); }
  /// In-place group product.
  SO2& operator*=(const SO2& other) { return *this = compose(other); }
  /// Rotation of a point.
  Point operator*(const Point& p) const { return rotate(p); }

  /// Right ⊕: this · exp(delta).
  SO2 oplus(const Tangent& delta) const { return compose(exp(delta)); }
  /// Right ⊖: log(other⁻¹ · this).
  Tangent ominus(const SO2& other) const { return other.inverse().compose(*this).log(); }

  /// Jr(θ) = 1 (Eq. 126).
  static Jacobian right_jacobian(const Tangent&) { return Jacobian::Ones(); }
  /// Jl(θ) = 1 (Eq. 126).
  static Jacobian left_jacobian(const Tangent&) { return Jacobian::Ones(); }
  /// Jr⁻¹(θ) = 1.
  static Jacobian right_jacobian_inverse(const Tangent&) { return Jacobian::Ones(); }
  /// Jl⁻¹(θ) = 1.
  static Jacobian left_jacobian_inverse(const Tangent&) { return Jacobian::Ones(); }

  /// Rotation matrix [[cos θ, −sin θ]; [sin θ, cos θ]].
  Matrix2<T> matrix() const {
    Matrix2<T> m;
    m << c_, -s_, s_, c_;
    return m;
  }
  /// Unit complex number (cos θ, sin θ).
  Vector2<T> unit_complex() const { return Vector2<T>(c_, s_); }

  /// The same rotation in scalar type U (renormalized in U).
  template <LieScalar U>
  SO2<U> cast() const {
    const U c = static_cast<U>(c_);
    const U s = static_cast<U>(s_);
    const U norm = std::hypot(c, s);
    return SO2<U>(c / norm, s / norm, typename SO2<U>::Unchecked{});
  }

  /// True when ‖(cos, sin)₁ − (cos, sin)₂‖ ≤ tol (≈ the angle difference in
  /// radians for small differences).
  bool is_approx(const SO2& other, T tol = default_approx_tolerance<T>()) const {
    return std::hypot(c_ - other.c_, s_ - other.s_) <= tol;
  }

 private:
  template <LieScalar>
  friend class SO2;
  template <LieScalar>
  friend class SE2;

  struct Unchecked {};
  SO2(T c, T s, Unchecked) : c_(c), s_(s) {}

  void set_normalized(T c, T s) {
    const T norm = std::hypot(c, s);
    c_ = c / norm;
    s_ = s / norm;
  }

  Point rotate(const Point& p) const {
    return Point(c_ * p.x() - s_ * p.y(), s_ * p.x() + c_ * p.y());
  }

  T c_;
  T s_;
};

/// Double-precision SO2.
using SO2d = SO2<double>;
/// Single-precision SO2.
using SO2f = SO2<float>;

}  // namespace rove
