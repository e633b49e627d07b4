#pragma once
/// \file
/// Robust kernels (M-estimators) for least squares, in the convention of g2o
/// and Ceres: a kernel maps a squared error s = ‖r‖² ≥ 0 (r whitened, i.e.
/// already multiplied by the square root of its information) to rho(s), and
/// gives rho'(s) and rho''(s). For small s every kernel behaves as least
/// squares: rho(s) ≈ s and rho'(0) = 1. The cost of a problem is ½ Σ rho(sᵢ);
/// its gradient is Σ rho'(sᵢ) Jᵢᵀ rᵢ, so the weight of a residual in
/// iteratively reweighted least squares (IRLS) is rho'(sᵢ).
///
/// Two ways to use them:
///  - compile-time structs (HuberKernel, CauchyKernel, ...) with inline
///    members, for hot loops without any dispatch;
///  - RobustKernel, a value chosen at run time (enum + parameter), built from
///    a text such as "huber" or "cauchy:2.0" by parse_robust_kernel().
///    RobustKernel::visit() hands the matching struct to a generic callable,
///    so a loop can be written once and dispatched once outside the loop.
///
/// Default parameters give 95% asymptotic efficiency on unit-variance
/// Gaussian residuals (Huber 1.345, Cauchy 2.3849, Tukey 4.6851; Zhang,
/// "Parameter estimation techniques: a tutorial with application to conic
/// fitting", 1997, Table 1). All parameters are in the units of the whitened
/// residual r (not of s).

#include <cmath>
#include <concepts>
#include <string>
#include <string_view>

#include "rove/core/check.h"

namespace rove {

/// rho(s), rho'(s) and rho''(s) of a robust kernel at one squared error s.
struct KernelValues {
  double rho = 0.0;  ///< rho(s)
  double d1 = 0.0;   ///< rho'(s), also the IRLS weight
  double d2 = 0.0;   ///< rho''(s)
};

/// What a compile-time kernel provides: evaluate(s) → KernelValues and
/// weight(s) → rho'(s), for a squared error s ≥ 0.
template <typename K>
concept RobustKernelFunction = requires(const K& k, double s) {
  { k.evaluate(s) } -> std::same_as<KernelValues>;
  { k.rho(s) } -> std::convertible_to<double>;
  { k.weight(s) } -> std::convertible_to<double>;
};

namespace detail {
/// Precondition shared by every kernel: s is a squared error, so s ≥ 0 (and
/// not NaN; +inf is accepted and gives the kernel's limit).
inline void check_squared_error(double s) {
  ROVE_CHECK_MSG(s >= 0.0, "a robust kernel takes a squared error s >= 0, got s = {}", s);
}
/// Precondition shared by every kernel parameter: finite and > 0.
inline void check_kernel_parameter(double p, const char* name) {
  ROVE_CHECK_MSG(std::isfinite(p) && p > 0.0,
                 "robust kernel parameter {} must be finite and > 0, got {}", name, p);
}
}  // namespace detail

/// Plain least squares: rho(s) = s. Weight 1 everywhere.
struct TrivialKernel {
  /// rho, rho', rho'' at squared error s ≥ 0.
  KernelValues evaluate(double s) const {
    detail::check_squared_error(s);
    return {s, 1.0, 0.0};
  }
  /// rho(s) = s.
  double rho(double s) const { return evaluate(s).rho; }
  /// IRLS weight rho'(s) = 1.
  double weight(double s) const { return evaluate(s).d1; }
};

/// Huber: quadratic up to |r| = delta, linear beyond.
/// rho(s) = s for s ≤ δ², 2δ√s − δ² otherwise (rho and rho' continuous).
struct HuberKernel {
  /// δ > 0: residual magnitude (whitened units) where the cost turns linear.
  double delta = 1.345;

  HuberKernel() = default;
  /// Precondition: delta finite and > 0.
  explicit HuberKernel(double delta_) : delta(delta_) {
    detail::check_kernel_parameter(delta, "delta");
  }
  /// rho, rho', rho'' at squared error s ≥ 0.
  KernelValues evaluate(double s) const {
    detail::check_squared_error(s);
    const double d2 = delta * delta;
    if (s <= d2) return {s, 1.0, 0.0};
    const double r = std::sqrt(s);
    return {2.0 * delta * r - d2, delta / r, -0.5 * delta / (s * r)};
  }
  /// rho(s).
  double rho(double s) const { return evaluate(s).rho; }
  /// IRLS weight rho'(s) = min(1, δ/√s).
  double weight(double s) const { return evaluate(s).d1; }
};

/// Cauchy (Lorentzian): rho(s) = c² log(1 + s/c²). Grows logarithmically.
struct CauchyKernel {
  /// c > 0: scale (whitened units); the weight is ½ at |r| = c.
  double c = 2.3849;

  CauchyKernel() = default;
  /// Precondition: c finite and > 0.
  explicit CauchyKernel(double c_) : c(c_) { detail::check_kernel_parameter(c, "c"); }
  /// rho, rho', rho'' at squared error s ≥ 0.
  KernelValues evaluate(double s) const {
    detail::check_squared_error(s);
    const double b = c * c;
    const double inv = 1.0 / (1.0 + s / b);
    return {b * std::log1p(s / b), inv, -inv * inv / b};
  }
  /// rho(s).
  double rho(double s) const { return evaluate(s).rho; }
  /// IRLS weight rho'(s) = 1 / (1 + s/c²).
  double weight(double s) const { return evaluate(s).d1; }
};

/// Tukey's biweight: rho(s) = c²/3 (1 − (1 − s/c²)³) for s ≤ c², c²/3
/// beyond. Residuals larger than c get zero weight (a redescending kernel).
struct TukeyKernel {
  /// c > 0: residual magnitude (whitened units) beyond which the weight is 0.
  double c = 4.6851;

  TukeyKernel() = default;
  /// Precondition: c finite and > 0.
  explicit TukeyKernel(double c_) : c(c_) { detail::check_kernel_parameter(c, "c"); }
  /// rho, rho', rho'' at squared error s ≥ 0.
  KernelValues evaluate(double s) const {
    detail::check_squared_error(s);
    const double b = c * c;
    if (s > b) return {b / 3.0, 0.0, 0.0};
    const double u = 1.0 - s / b;
    return {b / 3.0 * (1.0 - u * u * u), u * u, -2.0 * u / b};
  }
  /// rho(s).
  double rho(double s) const { return evaluate(s).rho; }
  /// IRLS weight rho'(s) = (1 − s/c²)² inside, 0 outside.
  double weight(double s) const { return evaluate(s).d1; }
};

/// Geman–McClure: rho(s) = s / (1 + s/c²) = c² s / (c² + s), bounded by c².
struct GemanMcClureKernel {
  /// c > 0: scale (whitened units); rho tends to c² for large errors.
  double c = 1.0;

  GemanMcClureKernel() = default;
  /// Precondition: c finite and > 0.
  explicit GemanMcClureKernel(double c_) : c(c_) { detail::check_kernel_parameter(c, "c"); }
  /// rho, rho', rho'' at squared error s ≥ 0.
  KernelValues evaluate(double s) const {
    detail::check_squared_error(s);
    const double b = c * c;
    if (std::isinf(s)) return {b, 0.0, 0.0};
    const double den = b + s;
    const double q = b / den;
    return {s * q, q * q, -2.0 * q * q / den};
  }
  /// rho(s).
  double rho(double s) const { return evaluate(s).rho; }
  /// IRLS weight rho'(s) = c⁴ / (c² + s)².
  double weight(double s) const { return evaluate(s).d1; }
};

/// Dynamic covariance scaling (Agarwal, Tipaldi, Spinello, Stachniss,
/// Burgard, "Robust map optimization using dynamic covariance scaling",
/// ICRA 2013). Eq. (14) there scales a residual by
/// σ = min(1, 2Φ / (Φ + s)), i.e. weights it by σ². This kernel is the one
/// whose IRLS weight is exactly that: rho'(s) = σ(s)², integrated to
///   rho(s) = s                 for s ≤ Φ,
///   rho(s) = 3Φ − 4Φ²/(Φ + s)  for s > Φ   (rho → 3Φ, continuous rho').
/// g2o's RobustKernelDCS reports rho = σ² s instead, which is not the
/// integral of its weight; weights (and hence IRLS steps) agree.
struct DcsKernel {
  /// Φ > 0, in squared whitened units: errors with s ≤ Φ keep full weight.
  double phi = 1.0;

  DcsKernel() = default;
  /// Precondition: phi finite and > 0.
  explicit DcsKernel(double phi_) : phi(phi_) { detail::check_kernel_parameter(phi, "phi"); }
  /// rho, rho', rho'' at squared error s ≥ 0.
  KernelValues evaluate(double s) const {
    detail::check_squared_error(s);
    if (s <= phi) return {s, 1.0, 0.0};
    if (std::isinf(s)) return {3.0 * phi, 0.0, 0.0};
    const double den = phi + s;
    const double q = 2.0 * phi / den;  // the scale σ of Eq. (14)
    return {3.0 * phi - 2.0 * phi * q, q * q, -2.0 * q * q / den};
  }
  /// rho(s).
  double rho(double s) const { return evaluate(s).rho; }
  /// IRLS weight rho'(s) = min(1, 2Φ/(Φ + s))².
  double weight(double s) const { return evaluate(s).d1; }
};

static_assert(RobustKernelFunction<TrivialKernel> && RobustKernelFunction<HuberKernel> &&
              RobustKernelFunction<CauchyKernel> && RobustKernelFunction<TukeyKernel> &&
              RobustKernelFunction<GemanMcClureKernel> && RobustKernelFunction<DcsKernel>);

/// The kernels selectable at run time.
enum class RobustKernelType { Trivial, Huber, Cauchy, Tukey, GemanMcClure, Dcs };

/// Lower-case name of a kernel type as parse_robust_kernel() accepts it:
/// "none", "huber", "cauchy", "tukey", "geman_mcclure", "dcs".
std::string_view to_string(RobustKernelType type);

/// Default parameter of a kernel type (0 for Trivial, which has none).
double default_kernel_parameter(RobustKernelType type);

/// A robust kernel chosen at run time: a type and its parameter (δ for
/// Huber, c for Cauchy/Tukey/Geman–McClure, Φ for DCS; unused for Trivial).
/// A small value type; evaluate() dispatches with a switch, no virtual call.
class RobustKernel {
 public:
  /// Plain least squares.
  RobustKernel() = default;
  /// The given type with its default parameter.
  explicit RobustKernel(RobustKernelType type);
  /// The given type and parameter. Precondition: parameter finite and > 0
  /// (ignored, and unchecked, for Trivial).
  RobustKernel(RobustKernelType type, double parameter);

  /// Kernel type.
  RobustKernelType type() const noexcept { return type_; }
  /// Kernel parameter (see the class comment for its meaning).
  double parameter() const noexcept { return parameter_; }

  /// Calls f with the compile-time kernel struct of this type and returns
  /// its result, so that a hot loop placed inside f is dispatched once.
  template <typename F>
  decltype(auto) visit(F&& f) const {
    switch (type_) {
      case RobustKernelType::Huber: return f(HuberKernel(parameter_));
      case RobustKernelType::Cauchy: return f(CauchyKernel(parameter_));
      case RobustKernelType::Tukey: return f(TukeyKernel(parameter_));
      case RobustKernelType::GemanMcClure: return f(GemanMcClureKernel(parameter_));
      case RobustKernelType::Dcs: return f(DcsKernel(parameter_));
      case RobustKernelType::Trivial: break;
    }
    return f(TrivialKernel{});
  }

  /// rho, rho', rho'' at squared error s ≥ 0.
  KernelValues evaluate(double s) const {
    return visit([s](const auto& k) { return k.evaluate(s); });
  }
  /// rho(s).
  double rho(double s) const { return evaluate(s).rho; }
  /// IRLS weight rho'(s).
  double weight(double s) const { return evaluate(s).d1; }

  /// Text that parse_robust_kernel() reads back to an equal kernel, e.g.
  /// "cauchy:2.3849" or "none".
  std::string to_string() const;

  /// Same type and parameter.
  friend bool operator==(const RobustKernel&, const RobustKernel&) = default;

 private:
  RobustKernelType type_ = RobustKernelType::Trivial;
  double parameter_ = 0.0;
};

/// Builds a kernel from text "name" or "name:parameter", case-insensitive,
/// surrounding blanks ignored. Names: none (or trivial, l2), huber, cauchy,
/// tukey, geman_mcclure (or gm), dcs. Without a parameter the default is
/// used. Throws rove::ParseError (source = `source`, field "robust kernel")
/// for an unknown name, a malformed or non-positive parameter, or a parameter
/// given to "none".
RobustKernel parse_robust_kernel(std::string_view text,
                                 std::string_view source = "<robust kernel>");

}  // namespace rove
