#pragma once
// Pieces of icp_2d shared by the default path (icp_2d.cpp) and the
// reproduction of MRPT's arithmetic (icp_2d_mrpt.cpp, Arithmetic::Mrpt).

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "rove/maps/kdtree.h"
#include "rove/poses/pose2.h"
#include "rove/registration/icp_2d.h"
#include "rove/registration/icp_target_2d.h"

namespace rove::detail {

/// One pair of a pairing.
struct Icp2dPair {
  std::uint32_t source = 0;  // index into the source span
  std::uint32_t target = 0;  // index into target.points()
  double sq_dist = 0;        // squared distance at pairing, m²
};

/// The pairs of one pairing and the scratch kept across iterations.
struct Icp2dMatching {
  std::vector<Icp2dPair> pairs;
  std::size_t sources_with_pair = 0;
  std::size_t sources_considered = 0;
  /// onlyUniqueRobust scratch: per target point, the index in `pairs` of its
  /// closest pair so far (kNone when untouched). Sized once per icp_2d call
  /// and reset entry by entry, so a pairing costs O(pairs), not O(target).
  std::vector<std::uint32_t> best_of_target;
  /// Per source point, its nearest target point at the last pairing that
  /// considered it (kNone: none yet). Its distance bounds the next search
  /// (see icp2d_match_range). Sized once per icp_2d call.
  std::vector<std::uint32_t> last_partner;
  static constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
};

/// What one pairing of a range of source points needs.
struct Icp2dMatchInput {
  std::span<const Eigen::Vector2d> source;
  double c = 1, s = 0;                        // cos, sin of the pose's rotation
  Eigen::Vector2d t = Eigen::Vector2d::Zero();  // the pose's translation
  Eigen::Vector2d pivot = Eigen::Vector2d::Zero();
  double thr = 0, thr_ang = 0;  // gate: thr_ang·‖p − pivot‖ + thr
  std::size_t offset = 0, decimation = 1;
  bool only_closest = true;
};

/// Pairs the source points k·decimation + offset, k in [b, e), appending to
/// `pairs`; returns how many of them found a pair. MRPT's
/// CPointsMap::determineMatching2D (as Debian builds MRPT 2.5.8, without its
/// hand-written SSE2 paths) in the arithmetic of the tree: each point is
/// moved by (x₀ + cos·x) − sin·y in Scalar, its squared distance to the
/// nearest target point is the tree's, and the gate is computed in double.
/// With Scalar = float (instantiated in icp_2d_mrpt.cpp) pairs at the gate
/// fall on the same side as MRPT's. `last_partner` (one entry per source
/// point) bounds each nearest search by the point's previous partner (the
/// same result as an unbounded search: the pose moves little between
/// iterations).
template <typename Scalar>
std::size_t icp2d_match_range(const KdTree<2, Scalar>& tree, const Icp2dMatchInput& in,
                              std::size_t b, std::size_t e, std::vector<Icp2dPair>& pairs,
                              std::vector<Neighbor<Scalar>>& nbrs, std::uint32_t* last_partner) {
  using Vec = Eigen::Matrix<Scalar, 2, 1>;
  std::size_t with_pair = 0;
  const Scalar c = static_cast<Scalar>(in.c), s = static_cast<Scalar>(in.s);
  const Scalar tx = static_cast<Scalar>(in.t.x()), ty = static_cast<Scalar>(in.t.y());
  for (std::size_t k = b; k < e; ++k) {
    const std::size_t i = in.offset + k * in.decimation;
    const Eigen::Vector2d& p = in.source[i];
    if (!p.allFinite()) continue;
    const Scalar px = static_cast<Scalar>(p.x()), py = static_cast<Scalar>(p.y());
    const Scalar lx = tx + c * px - s * py;
    const Scalar ly = ty + s * px + c * py;
    const double dx = in.pivot.x() - lx, dy = in.pivot.y() - ly;
    const double gate = in.thr_ang * std::sqrt(dx * dx + dy * dy) + in.thr;
    if (in.only_closest) {
      // The search is bounded by the gate (inclusive, a hair wider: the test
      // below is MRPT's, a Scalar distance against a double gate, strict).
      std::uint32_t& lp = last_partner[i];
      const auto nn = tree.nearest(Vec(lx, ly), static_cast<Scalar>(gate * (1 + 1e-6)), lp);
      lp = nn ? nn->index : Icp2dMatching::kNone;
      if (!nn) continue;
      if (nn->sq_distance < gate * gate) {
        pairs.push_back({static_cast<std::uint32_t>(i), nn->index, nn->sq_distance});
        ++with_pair;
      }
    } else {
      tree.radius(Vec(lx, ly), static_cast<Scalar>(gate), nbrs, false);
      bool any = false;
      for (const auto& nb : nbrs) {
        if (nb.sq_distance < gate * gate) {
          pairs.push_back({static_cast<std::uint32_t>(i), nb.index, nb.sq_distance});
          any = true;
        }
      }
      if (any) ++with_pair;
    }
  }
  return with_pair;
}

extern template std::size_t icp2d_match_range(const KdTree<2, float>&, const Icp2dMatchInput&,
                                              std::size_t, std::size_t, std::vector<Icp2dPair>&,
                                              std::vector<Neighbor<float>>&, std::uint32_t*);
extern template std::size_t icp2d_match_range(const KdTree<2, double>&, const Icp2dMatchInput&,
                                              std::size_t, std::size_t, std::vector<Icp2dPair>&,
                                              std::vector<Neighbor<double>>&, std::uint32_t*);

/// The slope at w2 of the parabola through (w1, q1), (w2, q2), (w3, q3):
/// MRPT's three-point derivative of its LM gradient, in its order of
/// operations (double).
inline double parabola_slope(double w1, double w2, double w3, double q1, double q2, double q3) {
  const double a = ((q3 - q2) / ((w3 - w2) * (w3 - w1))) - ((q1 - q2) / ((w1 - w2) * (w3 - w1)));
  const double b = ((q1 - q2) + (a * ((w2 * w2) - (w1 * w1)))) / (w1 - w2);
  return (2 * a * w2) + b;
}

/// MRPT's damping rule in its LM: a step that lowers the sum of squared
/// errors is taken and λ ÷ 10, else λ × 10.
inline void lm_accept_or_damp(const Pose2& q_new, double ose_new, Pose2& q, double& ose,
                              double& lambda) {
  if (ose_new < ose) {
    lambda /= 10;
    q = q_new;
    ose = ose_new;
  } else {
    lambda *= 10;
  }
}

// ---- Arithmetic::Mrpt (icp_2d_mrpt.cpp) ---------------------------------

/// The options as MRPT holds them: the [ICP] values MRPT reads with
/// read_float (its fields are double, its reads are not) are the nearest
/// float, given or default (thresholdDist = 0.3 is 0.30000001192…), and the
/// angles in degrees go through MRPT's float DEG2RAD.
Icp2dOptions mrpt_rounded_options(Icp2dOptions o);

/// MRPT's tfest::se2_l2 (Martínez et al., J. Field Robotics 2006) in its
/// single-precision arithmetic: raw sums of the coordinates and of their
/// products in pair order, Ax = N·(Σxa·xb + Σya·yb) − Σxa·Σxb − Σya·Σyb,
/// Ay = Σxa·Σyb + N·(Σya·xb − Σxa·yb) − Σxb·Σya, φ = atan2(Ay, Ax).
Pose2 mrpt_se2_l2_fit(const IcpTarget2D& target, std::span<const Eigen::Vector2d> source,
                      const std::vector<Icp2dPair>& pairs);

/// One pairing of MRPT's icpLevenbergMarquardt in MRPT 2.5.8's arithmetic
/// (see icp_2d_mrpt.cpp). The target must be built with Arithmetic::Mrpt.
Pose2 mrpt_finite_difference_lm(const IcpTarget2D& target, std::span<const Eigen::Vector2d> source,
                                const std::vector<Icp2dPair>& pairs, Pose2 q,
                                const Icp2dOptions& o);

/// MRPT's correspondencesRatio in its float arithmetic: decimation ×
/// (points with a pair) / (finite points).
double mrpt_goodness(std::size_t decimation, std::size_t with_pair, std::size_t finite_points);

}  // namespace rove::detail
