#include "rove/maps/kdtree.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <utility>

#include "rove/core/check.h"
#include "rove/core/cpu.h"

#if defined(__SSE2__)
#include <emmintrin.h>
#endif
#if ROVE_AVX2_KERNELS
#include <immintrin.h>
#endif

namespace rove {

namespace {

constexpr std::uint32_t kNotIndexed = std::numeric_limits<std::uint32_t>::max();

template <typename Scalar, int Dim>
bool finite_point(const Scalar* p) {
  for (int i = 0; i < Dim; ++i)
    if (!std::isfinite(p[i])) return false;
  return true;
}

/// The next representable value above a square x (x >= +0; +inf stays):
/// std::nextafter(x, +inf) without its library call, which cost 2 % of a
/// whole `rove icp-slam` run (one per bounded search).
template <typename Scalar>
Scalar next_up(Scalar x) {
  if (!(x < std::numeric_limits<Scalar>::infinity())) return x;
  using Bits = std::conditional_t<sizeof(Scalar) == 4, std::uint32_t, std::uint64_t>;
  static_assert(sizeof(Bits) == sizeof(Scalar));
  Bits b;
  std::memcpy(&b, &x, sizeof b);
  ++b;  // a non-negative IEEE value orders as its bit pattern
  std::memcpy(&x, &b, sizeof b);
  return x;
}

/// Axis-aligned bounding box of a range of points.
template <int Dim, typename Scalar>
struct Box {
  std::array<Scalar, Dim> lo;
  std::array<Scalar, Dim> hi;
};

/// One tree node, stored in depth-first order so that an inner node's left
/// child follows it. A leaf holds the tree positions [first, last) with
/// first < last. An inner node holds the position of its right child in
/// `first` and the split dimension in `last` (< Dim), so last < first tells
/// the two apart (the right child of any node is at position >= 2). `low` is
/// the largest coordinate along the split dimension in the left child, `high`
/// the smallest in the right child (low <= high).
template <typename Scalar>
struct Node {
  std::uint32_t first;
  std::uint32_t last;
  Scalar low;
  Scalar high;
  bool is_leaf() const { return first < last; }
};

/// Squared Euclidean distance, summed over d in order (as the brute force the
/// tests compare against).
template <int Dim, typename Scalar>
Scalar sq_distance(const Scalar* a, const Scalar* b) {
  Scalar s = 0;
  for (int d = 0; d < Dim; ++d) {
    const Scalar diff = a[d] - b[d];
    s += diff * diff;
  }
  return s;
}

/// Keeps the single nearest point strictly closer than `worst`.
template <typename Scalar>
struct NearestSet {
  Scalar worst;
  std::uint32_t position = kNotIndexed;
  Scalar bound() const { return worst; }
  void add(Scalar d, std::uint32_t pos) {
    worst = d;
    position = pos;
  }
};

/// Keeps the k nearest points in `out` (source indices), sorted nearest
/// first; points at the distance of the current k-th are not admitted.
template <typename Scalar>
struct KnnSet {
  Neighbor<Scalar>* out;
  std::size_t k;
  const std::uint32_t* source_of;
  std::size_t count = 0;
  Scalar worst = std::numeric_limits<Scalar>::infinity();
  Scalar bound() const { return worst; }
  void add(Scalar d, std::uint32_t pos) {
    std::size_t i = count < k ? count++ : k - 1;
    while (i > 0 && out[i - 1].sq_distance > d) {
      out[i] = out[i - 1];
      --i;
    }
    out[i] = Neighbor<Scalar>{source_of[pos], d};
    if (count == k) worst = out[k - 1].sq_distance;
  }
};

/// The state of SmallKnnSet and WideKnnSet: the k nearest so far in
/// arrays of N entries aligned to Align bytes, ascending, the entries not
/// yet filled holding the admission bound.
template <std::size_t N, std::size_t Align>
struct KnnArrays {
  std::size_t k;
  std::size_t count = 0;
  alignas(Align) float dist[N];
  alignas(Align) std::uint32_t pos[N];
  float worst;
  KnnArrays(std::size_t k_, float bound) : k(k_), worst(bound) {
    for (std::size_t j = 0; j < N; ++j) {
      dist[j] = bound;
      pos[j] = kNotIndexed;
    }
  }
  float bound() const { return worst; }
  /// After an insertion: one more found (up to k), and the new bound.
  void inserted() {
    count += count < k ? 1 : 0;
    worst = dist[k - 1];
  }
  std::size_t write(Neighbor<float>* out, const std::uint32_t* source_of) const {
    for (std::size_t j = 0; j < count; ++j) out[j] = Neighbor<float>{source_of[pos[j]], dist[j]};
    return count;
  }
};

/// KnnSet for float distances and k <= N, with no branch on the data: the
/// distances and positions live in arrays of N entries, those not yet
/// filled holding the admission bound, and an insertion rewrites every
/// entry j as min(d[j], max(d[j − 1], x)) (the sorted array with x inserted
/// and its last entry dropped; ties keep the earlier point first, as
/// KnnSet), four entries at a time in SSE2 compares and blends. KnnSet's
/// insertion sort mispredicted the exit of its loop about once per admitted
/// point; this set took 12-15 % less time for k = 10 and 7 % less for
/// k = 20 over every point of a 0.25 m voxel cloud (bench/RESULTS.md,
/// bench_kdtree_vs_nanoflann).
///
/// Every load and store is an aligned group of four, and d[j − 1] comes
/// from the groups already in registers (a lane shift), not from a load
/// one entry off: such a load overlaps two stores of the previous
/// insertion, which are often still in the store buffer, and cannot be
/// forwarded from them.
template <std::size_t N>
struct SmallKnnSet : KnnArrays<N, 16> {
  static_assert(N % 4 == 0, "whole SSE2 groups");
  using KnnArrays<N, 16>::KnnArrays;
  using KnnArrays<N, 16>::dist;
  using KnnArrays<N, 16>::pos;
  /// Precondition: x < bound().
  void add(float x, std::uint32_t p) {
#if defined(__SSE2__)
    const __m128 vx = _mm_set1_ps(x);
    const __m128i vp = _mm_set1_epi32(static_cast<int>(p));
    // The group before the first: d = −inf (never shifted), no position.
    __m128i prev_d = _mm_castps_si128(_mm_set1_ps(-std::numeric_limits<float>::infinity()));
    __m128i prev_p = _mm_set1_epi32(static_cast<int>(kNotIndexed));
    for (std::size_t j = 0; j < N; j += 4) {
      const __m128i here_d = _mm_load_si128(reinterpret_cast<const __m128i*>(dist + j));
      const __m128i here_p = _mm_load_si128(reinterpret_cast<const __m128i*>(pos + j));
      // Entries j − 1 .. j + 2: this group moved up one lane, the previous
      // group's last entry in lane 0.
      const __m128 here = _mm_castsi128_ps(here_d);
      const __m128 before = _mm_castsi128_ps(_mm_or_si128(_mm_slli_si128(here_d, 4), _mm_srli_si128(prev_d, 12)));
      const __m128i before_p = _mm_or_si128(_mm_slli_si128(here_p, 4), _mm_srli_si128(prev_p, 12));
      // keep: here <= x (the entry stays); shift: before > x (it moves up).
      const __m128i keep = _mm_castps_si128(_mm_cmple_ps(here, vx));
      const __m128i shift = _mm_castps_si128(_mm_cmpgt_ps(before, vx));
      // min(here, max(before, x)), with _mm_max_ps(a, b) = a > b ? a : b
      // and _mm_min_ps(a, b) = a < b ? a : b.
      const __m128 nd = _mm_min_ps(here, _mm_max_ps(before, vx));
      const __m128i moved = _mm_or_si128(_mm_and_si128(shift, before_p), _mm_andnot_si128(shift, vp));
      const __m128i np = _mm_or_si128(_mm_and_si128(keep, here_p), _mm_andnot_si128(keep, moved));
      _mm_store_ps(dist + j, nd);
      _mm_store_si128(reinterpret_cast<__m128i*>(pos + j), np);
      prev_d = here_d;
      prev_p = here_p;
    }
#else
    // The same per entry, one at a time.
    float before = -std::numeric_limits<float>::infinity();
    std::uint32_t before_p = kNotIndexed;
    for (std::size_t j = 0; j < N; ++j) {
      const float here = dist[j];
      const std::uint32_t here_p = pos[j];
      const float larger = before > x ? before : x;
      dist[j] = here < larger ? here : larger;
      pos[j] = here <= x ? here_p : before > x ? before_p : p;
      before = here;
      before_p = here_p;
    }
#endif
    this->inserted();
  }
};

#if ROVE_AVX2_KERNELS
/// SmallKnnSet in AVX2 groups of eight (N a multiple of 8), for processors
/// that have it: the same entries after every insertion.
template <std::size_t N>
struct WideKnnSet : KnnArrays<N, 32> {
  static_assert(N % 8 == 0, "whole AVX2 groups");
  using KnnArrays<N, 32>::KnnArrays;
  using KnnArrays<N, 32>::dist;
  using KnnArrays<N, 32>::pos;
  __attribute__((target("avx2"), noinline)) void add(float x, std::uint32_t p) {
    const __m256 vx = _mm256_set1_ps(x);
    const __m256i vp = _mm256_set1_epi32(static_cast<int>(p));
    // Lane i takes lane i − 1; lane 0 takes lane 7 (then replaced by the
    // previous group's last entry).
    const __m256i up = _mm256_setr_epi32(7, 0, 1, 2, 3, 4, 5, 6);
    __m256 prev_d = _mm256_set1_ps(-std::numeric_limits<float>::infinity());
    __m256 prev_p = _mm256_castsi256_ps(_mm256_set1_epi32(static_cast<int>(kNotIndexed)));
    for (std::size_t j = 0; j < N; j += 8) {
      const __m256 here = _mm256_load_ps(dist + j);
      const __m256 here_p = _mm256_load_ps(reinterpret_cast<const float*>(pos + j));
      const __m256 rot = _mm256_permutevar8x32_ps(here, up);
      const __m256 rot_p = _mm256_permutevar8x32_ps(here_p, up);
      const __m256 before = _mm256_blend_ps(rot, prev_d, 0x01);
      const __m256 before_p = _mm256_blend_ps(rot_p, prev_p, 0x01);
      const __m256 keep = _mm256_cmp_ps(here, vx, _CMP_LE_OQ);
      const __m256 shift = _mm256_cmp_ps(before, vx, _CMP_GT_OQ);
      const __m256 nd = _mm256_min_ps(here, _mm256_max_ps(before, vx));
      const __m256 moved = _mm256_blendv_ps(_mm256_castsi256_ps(vp), before_p, shift);
      const __m256 np = _mm256_blendv_ps(moved, here_p, keep);
      _mm256_store_ps(dist + j, nd);
      _mm256_store_ps(reinterpret_cast<float*>(pos + j), np);
      prev_d = rot;  // its lane 0 is this group's last entry
      prev_p = rot_p;
    }
    this->inserted();
  }
};
#endif

/// Collects every point with distance < bound (source indices).
template <typename Scalar>
struct RadiusSet {
  std::vector<Neighbor<Scalar>>& out;
  const std::uint32_t* source_of;
  Scalar worst;
  Scalar bound() const { return worst; }
  void add(Scalar d, std::uint32_t pos) { out.push_back(Neighbor<Scalar>{source_of[pos], d}); }
};

/// Sorts neighbors by distance, then index. For float, a Neighbor is two
/// 32-bit words, {index, sq_distance}; a non-negative float orders as its bit
/// pattern, so (sq_distance bits << 32 | index) is the sort key.
template <typename Scalar>
void sort_neighbors(std::vector<Neighbor<Scalar>>& v) {
  if constexpr (std::is_same_v<Scalar, float> && sizeof(Neighbor<float>) == 8) {
    const auto key = [](const Neighbor<float>& n) {
      std::uint32_t bits;
      std::memcpy(&bits, &n.sq_distance, sizeof bits);
      return (static_cast<std::uint64_t>(bits) << 32) | n.index;
    };
    std::sort(v.begin(), v.end(), [&](const Neighbor<float>& a, const Neighbor<float>& b) { return key(a) < key(b); });
  } else {
    std::sort(v.begin(), v.end(), [](const Neighbor<Scalar>& a, const Neighbor<Scalar>& b) {
      return a.sq_distance < b.sq_distance || (a.sq_distance == b.sq_distance && a.index < b.index);
    });
  }
}

}  // namespace

template <int Dim, typename Scalar>
struct KdTree<Dim, Scalar>::Impl {
  using BoxT = Box<Dim, Scalar>;
  using NodeT = Node<Scalar>;

  KdTreeOptions options;
  std::size_t source_size = 0;
  std::vector<Point> points;               // indexed points, tree order
  std::vector<std::uint32_t> source_of;    // tree position -> source index
  std::vector<std::uint32_t> position_of;  // source index -> tree position (or kNotIndexed)
  std::vector<NodeT> nodes;                // depth-first; nodes[0] is the root
  BoxT box{};                              // bounding box of all points
  // For searches that start near a hint instead of at the root: each node's
  // parent (the root's: kNotIndexed), each node's cell (the region of space
  // its points were split into; a face the cell inherits from the root box
  // is open, ±inf, since no point lies beyond it), and each point's leaf.
  std::vector<std::uint32_t> parent;
  std::vector<BoxT> cells;
  std::vector<std::uint32_t> leaf_of;  // tree position -> leaf node
  // Inner nodes on the longest root-to-leaf path (the stack search() needs).
  std::size_t depth = 0;
  static constexpr std::size_t kStackDepth = 64;

  BoxT bounds(std::uint32_t first, std::uint32_t last) const {
    BoxT b;
    for (int d = 0; d < Dim; ++d) b.lo[d] = b.hi[d] = points[first][d];
    for (std::uint32_t i = first + 1; i < last; ++i)
      for (int d = 0; d < Dim; ++d) {
        const Scalar v = points[i][d];
        b.lo[d] = std::min(b.lo[d], v);
        b.hi[d] = std::max(b.hi[d], v);
      }
    return b;
  }

  void swap_points(std::uint32_t a, std::uint32_t b) {
    std::swap(points[a], points[b]);
    std::swap(source_of[a], source_of[b]);
  }

  /// Moves the points of [first, last) with coordinate d below `split` (or
  /// not above it, when kOrEqual) to the front; returns where they end.
  template <bool kOrEqual>
  std::uint32_t partition(std::uint32_t first, std::uint32_t last, int d, Scalar split) {
    std::uint32_t lo = first;
    std::uint32_t hi = last;
    const auto left = [&](std::uint32_t i) {
      if constexpr (kOrEqual) return points[i][d] <= split;
      else return points[i][d] < split;
    };
    for (;;) {
      while (lo < hi && left(lo)) ++lo;
      while (lo < hi && !left(hi - 1)) --hi;
      if (lo >= hi) return lo;
      swap_points(lo, hi - 1);
      ++lo;
      --hi;
    }
  }

  /// Builds the subtree over the points [first, last) (non-empty) of the
  /// cell `cell`; returns the bounding box of those points in `tight`.
  void build(std::uint32_t first, std::uint32_t last, const BoxT& cell, const BoxT& open_cell,
             std::uint32_t up, BoxT& tight, std::size_t level = 0) {
    const auto self = static_cast<std::uint32_t>(nodes.size());
    nodes.push_back(NodeT{first, last, 0, 0});
    parent.push_back(up);
    cells.push_back(open_cell);
    tight = bounds(first, last);
    const std::uint32_t count = last - first;
    if (count <= options.leaf_size) {
      for (std::uint32_t i = first; i < last; ++i) leaf_of[i] = self;
      depth = std::max(depth, level);
      return;
    }

    // Sliding midpoint (Maneewongvatana and Mount, "It's okay to be skinny,
    // if your friends are fat", CGC Workshop 1999): split the cell in the
    // middle of its widest side (of the near-widest sides, the one along
    // which the points spread most), sliding the split onto the points when
    // it misses them. lim1/lim2 then place the points equal to the split
    // value so that the halves are as even as the data allow; neither is
    // empty. The cell, not the points' bounding box, decides: on scans, whose
    // points lie on surfaces, halving the bounding box cut thin slabs and
    // made nearest queries on room_scan1 evaluate ten times more points.
    Scalar max_span = cell.hi[0] - cell.lo[0];
    for (int d = 1; d < Dim; ++d) max_span = std::max(max_span, cell.hi[d] - cell.lo[d]);
    int dim = 0;
    Scalar max_spread = -1;
    for (int d = 0; d < Dim; ++d) {
      if (cell.hi[d] - cell.lo[d] >= (1 - Scalar(1e-5)) * max_span && tight.hi[d] - tight.lo[d] > max_spread) {
        dim = d;
        max_spread = tight.hi[d] - tight.lo[d];
      }
    }
    const Scalar split =
        std::clamp(cell.lo[dim] * Scalar(0.5) + cell.hi[dim] * Scalar(0.5), tight.lo[dim], tight.hi[dim]);
    const std::uint32_t lim1 = partition<false>(first, last, dim, split) - first;
    const std::uint32_t lim2 = partition<true>(first + lim1, last, dim, split) - first;
    const std::uint32_t half = count / 2;
    const std::uint32_t cut = first + (lim1 > half ? lim1 : lim2 < half ? lim2 : half);

    BoxT left_cell = cell;
    left_cell.hi[dim] = split;
    BoxT right_cell = cell;
    right_cell.lo[dim] = split;
    BoxT left_open = open_cell;
    left_open.hi[dim] = split;
    BoxT right_open = open_cell;
    right_open.lo[dim] = split;
    BoxT left_tight;
    BoxT right_tight;
    build(first, cut, left_cell, left_open, self, left_tight, level + 1);
    const auto right = static_cast<std::uint32_t>(nodes.size());
    build(cut, last, right_cell, right_open, self, right_tight, level + 1);
    nodes[self] = NodeT{right, static_cast<std::uint32_t>(dim), left_tight.hi[dim], right_tight.lo[dim]};
  }

  /// Lower bound on the squared distance from q to `box`, per dimension in
  /// `dists`, summed in the return value.
  Scalar initial_distances(const Scalar* q, std::array<Scalar, Dim>& dists) const {
    Scalar sum = 0;
    for (int d = 0; d < Dim; ++d) {
      Scalar e = 0;
      if (q[d] < box.lo[d]) e = (q[d] - box.lo[d]) * (q[d] - box.lo[d]);
      if (q[d] > box.hi[d]) e = (q[d] - box.hi[d]) * (q[d] - box.hi[d]);
      dists[d] = e;
      sum += e;
    }
    return sum;
  }

  /// Depth-first search below node `n`. `min_sq` is a lower bound on the
  /// squared distance from q to the node's region, and dists[d] its part
  /// along dimension d, updated incrementally as the search crosses split
  /// planes (Arya and Mount, "Algorithms for fast vector quantization",
  /// DCC 1993, section 3). The near child first; the far child when its
  /// bound still admits points once the near side is done.
  ///
  /// Iterative, with the far children waiting on a stack of at most the
  /// tree's depth (one per level of the current path): the recursive form
  /// spent a third of a 3D k-nearest search on calls. A tree deeper than
  /// the fixed stack (only adversarial data) takes the recursive form; both
  /// visit the same nodes in the same order.
  ///
  /// Always inlined (as run() is), so that a caller compiled for AVX2
  /// (wide_knn) compiles the whole search for it.
  template <class Set>
  [[gnu::always_inline]] inline void search(std::uint32_t n, const Scalar* q, Scalar min_sq,
                                            std::array<Scalar, Dim>& dists, Set& set) const {
    if (depth > kStackDepth) {
      search_recursive(n, q, min_sq, dists, set);
      return;
    }
    struct Pending {
      std::uint32_t node;
      Scalar min_sq;
      std::array<Scalar, Dim> dists;
    };
    Pending stack[kStackDepth + 1];
    std::size_t top = 0;
    for (;;) {
      const NodeT* node = &nodes[n];
      while (!node->is_leaf()) {
        // Branch-free: which side is near depends on the data, so a branch
        // here is mispredicted half the time.
        const int dim = static_cast<int>(node->last);
        const Scalar v = q[dim];
        const Scalar to_low = v - node->low;
        const Scalar to_high = v - node->high;
        const bool left = to_low + to_high < 0;
        const std::uint32_t right_child = node->first;
        const std::uint32_t near_child = left ? n + 1 : right_child;
        const std::uint32_t far_child = left ? right_child : n + 1;
        const Scalar cut = left ? to_high * to_high : to_low * to_low;
        const Scalar far_sq = min_sq + cut - dists[dim];
        // The bound only shrinks: a far child it rejects now stays rejected.
        Pending& f = stack[top];
        f.node = far_child;
        f.min_sq = far_sq;
        f.dists = dists;
        f.dists[dim] = cut;
        top += far_sq <= set.bound() ? 1 : 0;
        n = near_child;
        node = &nodes[n];
      }
      for (std::uint32_t i = node->first; i < node->last; ++i) {
        const Scalar d = sq_distance<Dim, Scalar>(q, points[i].data());
        if (d < set.bound()) set.add(d, i);
      }
      // The next far child still admitted, deepest first.
      for (;;) {
        if (top == 0) return;
        const Pending& f = stack[--top];
        if (f.min_sq <= set.bound()) {
          n = f.node;
          min_sq = f.min_sq;
          dists = f.dists;
          break;
        }
      }
    }
  }

  /// The recursive form of search() (same nodes, same order), for trees
  /// deeper than its stack.
  template <class Set>
  void search_recursive(std::uint32_t n, const Scalar* q, Scalar min_sq, std::array<Scalar, Dim>& dists,
                        Set& set) const {
    const NodeT& node = nodes[n];
    if (node.is_leaf()) {
      for (std::uint32_t i = node.first; i < node.last; ++i) {
        const Scalar d = sq_distance<Dim, Scalar>(q, points[i].data());
        if (d < set.bound()) set.add(d, i);
      }
      return;
    }
    const int dim = static_cast<int>(node.last);
    const Scalar v = q[dim];
    const Scalar to_low = v - node.low;
    const Scalar to_high = v - node.high;
    std::uint32_t near_child;
    std::uint32_t far_child;
    Scalar cut;
    if (to_low + to_high < 0) {
      near_child = n + 1;
      far_child = node.first;
      cut = to_high * to_high;
    } else {
      near_child = node.first;
      far_child = n + 1;
      cut = to_low * to_low;
    }
    search_recursive(near_child, q, min_sq, dists, set);
    const Scalar saved = dists[dim];
    min_sq = min_sq + cut - saved;
    if (min_sq <= set.bound()) {
      dists[dim] = cut;
      search_recursive(far_child, q, min_sq, dists, set);
      dists[dim] = saved;
    }
  }

  template <class Set>
  [[gnu::always_inline]] inline void run(const Scalar* q, Set& set) const {
    std::array<Scalar, Dim> dists;
    const Scalar min_sq = initial_distances(q, dists);
    search(0, q, min_sq, dists, set);
  }

  /// The deepest node on the path from `leaf` to the root whose cell holds
  /// q with every face at squared distance >= bound: every point outside
  /// that node lies at least that far from q, so a search admitting only
  /// distances below `bound` finds nothing outside it. The root when no
  /// smaller node qualifies.
  ///
  /// Exact in floating point: for a point p beyond a face f along d,
  /// |q[d] − p[d]| >= |q[d] − f| holds after rounding too (rounding is
  /// monotone), and so does the sum of squares.
  std::uint32_t enclosing_node(std::uint32_t leaf, const Scalar* q, Scalar bound) const {
    std::uint32_t n = leaf;
    while (n != 0) {
      const BoxT& c = cells[n];
      bool inside = true;
      for (int d = 0; d < Dim && inside; ++d) {
        const Scalar below = q[d] - c.lo[d];
        const Scalar above = c.hi[d] - q[d];
        // NaN-free: q is finite, faces are finite or ±inf (then ±inf here,
        // and inf*inf >= bound).
        inside = below >= 0 && above >= 0 && below * below >= bound && above * above >= bound;
      }
      if (inside) return n;
      n = parent[n];
    }
    return 0;
  }

  /// As run(), starting from the smallest subtree around `leaf` that can
  /// hold every point the set admits (see enclosing_node). The same result
  /// as run(): outside that subtree no point is admitted, and inside it the
  /// nodes are visited in the same order (ties go the same way).
  template <class Set>
  void run_from(std::uint32_t leaf, const Scalar* q, Set& set) const {
    const std::uint32_t n = enclosing_node(leaf, q, set.bound());
    if (n == 0) {
      run(q, set);
      return;
    }
    std::array<Scalar, Dim> dists{};  // q lies in the node's cell
    search(n, q, Scalar(0), dists, set);
  }
};

#if ROVE_AVX2_KERNELS
/// The k nearest (k <= N) by a WideKnnSet, the whole search compiled for
/// AVX2 (run and search are inlined here).
template <std::size_t N, class Impl>
__attribute__((target("avx2"))) std::size_t wide_knn(const Impl& impl, const float* q, std::size_t k, float bound,
                                                     Neighbor<float>* out) {
  WideKnnSet<N> set(k, bound);
  impl.run(q, set);
  return set.write(out, impl.source_of.data());
}
#endif

template <int Dim, typename Scalar>
KdTree<Dim, Scalar>::KdTree() : KdTree(FinitePoints{}, KdTreeOptions{}) {}

template <int Dim, typename Scalar>
KdTree<Dim, Scalar>::KdTree(std::vector<Point> points, const KdTreeOptions& options)
    : KdTree(
          [&] {
            FinitePoints f;
            f.source_size = points.size();
            if (f.source_size >= std::size_t{kNotIndexed}) return f;  // rejected below
            f.source_index.resize(points.size());
            std::size_t w = 0;
            for (std::size_t i = 0; i < points.size(); ++i) {
              if (!finite_point<Scalar, Dim>(points[i].data())) continue;
              points[w] = points[i];
              f.source_index[w] = static_cast<std::uint32_t>(i);
              ++w;
            }
            points.resize(w);
            f.source_index.resize(w);
            f.points = std::move(points);
            return f;
          }(),
          options) {}

template <int Dim, typename Scalar>
KdTree<Dim, Scalar>::KdTree(FinitePoints finite, const KdTreeOptions& options) : impl_(std::make_unique<Impl>()) {
  ROVE_CHECK_GE(options.leaf_size, std::size_t{1});
  ROVE_CHECK_LT(finite.source_size, static_cast<std::size_t>(kNotIndexed));
  Impl& m = *impl_;
  m.options = options;
  m.source_size = finite.source_size;
  m.points = std::move(finite.points);
  m.source_of = std::move(finite.source_index);
  const auto n = static_cast<std::uint32_t>(m.points.size());
  if (n > 0) {
    // Partition the copy in place into tree order: every leaf then covers a
    // consecutive range of `points` and of `source_of`.
    m.nodes.reserve(2 * (n / std::max<std::size_t>(1, options.leaf_size / 2) + 1));
    m.parent.reserve(m.nodes.capacity());
    m.cells.reserve(m.nodes.capacity());
    m.leaf_of.resize(n);
    typename Impl::BoxT open;
    open.lo.fill(-std::numeric_limits<Scalar>::infinity());
    open.hi.fill(std::numeric_limits<Scalar>::infinity());
    m.build(0, n, m.bounds(0, n), open, kNotIndexed, m.box);
  }
  m.position_of.assign(m.source_size, kNotIndexed);
  for (std::uint32_t i = 0; i < n; ++i) m.position_of[m.source_of[i]] = i;
}

template <int Dim, typename Scalar>
KdTree<Dim, Scalar>::KdTree(KdTree&&) noexcept = default;
template <int Dim, typename Scalar>
KdTree<Dim, Scalar>& KdTree<Dim, Scalar>::operator=(KdTree&&) noexcept = default;
template <int Dim, typename Scalar>
KdTree<Dim, Scalar>::~KdTree() = default;

template <int Dim, typename Scalar>
std::size_t KdTree<Dim, Scalar>::size() const noexcept {
  return impl_ ? impl_->points.size() : 0;
}

template <int Dim, typename Scalar>
std::size_t KdTree<Dim, Scalar>::source_size() const noexcept {
  return impl_ ? impl_->source_size : 0;
}

template <int Dim, typename Scalar>
const KdTreeOptions& KdTree<Dim, Scalar>::options() const noexcept {
  static const KdTreeOptions kDefault;
  return impl_ ? impl_->options : kDefault;
}

template <int Dim, typename Scalar>
typename KdTree<Dim, Scalar>::Point KdTree<Dim, Scalar>::indexed_point(std::uint32_t source_index) const {
  ROVE_CHECK_LT(static_cast<std::size_t>(source_index), source_size());
  const std::uint32_t pos = impl_->position_of[source_index];
  ROVE_CHECK_MSG(pos != kNotIndexed, "point {} is not indexed (non-finite coordinates)", source_index);
  return impl_->points[pos];
}

template <int Dim, typename Scalar>
std::optional<Neighbor<Scalar>> KdTree<Dim, Scalar>::nearest(const Point& q) const {
  if (empty() || !finite_point<Scalar, Dim>(q.data())) return std::nullopt;
  NearestSet<Scalar> set{std::numeric_limits<Scalar>::infinity()};
  impl_->run(q.data(), set);
  if (set.position == kNotIndexed) return std::nullopt;
  return Result{impl_->source_of[set.position], set.worst};
}

template <int Dim, typename Scalar>
std::optional<Neighbor<Scalar>> KdTree<Dim, Scalar>::nearest(const Point& q, Scalar max_distance) const {
  ROVE_CHECK_GE(max_distance, Scalar(0));
  if (empty() || !finite_point<Scalar, Dim>(q.data())) return std::nullopt;
  // Points are admitted strictly below the bound; one ulp above
  // max_distance² makes that "distance <= max_distance" exactly.
  NearestSet<Scalar> set{next_up(max_distance * max_distance)};
  impl_->run(q.data(), set);
  if (set.position == kNotIndexed) return std::nullopt;
  return Result{impl_->source_of[set.position], set.worst};
}

template <int Dim, typename Scalar>
std::optional<Neighbor<Scalar>> KdTree<Dim, Scalar>::nearest(const Point& q, Scalar max_distance,
                                                            std::uint32_t hint) const {
  ROVE_CHECK_GE(max_distance, Scalar(0));
  if (empty() || !finite_point<Scalar, Dim>(q.data())) return std::nullopt;
  Scalar bound = next_up(max_distance * max_distance);
  std::uint32_t hint_leaf = kNotIndexed;
  if (hint < impl_->source_size) {
    // The hint's distance in the search's own arithmetic: one ulp above it
    // admits the hint, so the nearest within the bound is the nearest
    // within max_distance (the same point, ties included: the visiting
    // order does not change, only what is pruned).
    const std::uint32_t pos = impl_->position_of[hint];
    if (pos != kNotIndexed) {
      const Scalar d = sq_distance<Dim, Scalar>(q.data(), impl_->points[pos].data());
      if (d < bound) bound = next_up(d);
      hint_leaf = impl_->leaf_of[pos];
    }
  }
  NearestSet<Scalar> set{bound};
  if (hint_leaf != kNotIndexed) impl_->run_from(hint_leaf, q.data(), set);
  else impl_->run(q.data(), set);
  if (set.position == kNotIndexed) return std::nullopt;
  return Result{impl_->source_of[set.position], set.worst};
}

template <int Dim, typename Scalar>
std::size_t KdTree<Dim, Scalar>::knn(const Point& q, std::size_t k, std::span<Result> out) const {
  return knn(q, k, out, std::numeric_limits<Scalar>::infinity());
}

template <int Dim, typename Scalar>
std::size_t KdTree<Dim, Scalar>::knn(const Point& q, std::size_t k, std::span<Result> out,
                                     Scalar max_distance) const {
  ROVE_CHECK_GE(out.size(), k);
  ROVE_CHECK_GE(max_distance, Scalar(0));
  if (k == 0 || empty() || !finite_point<Scalar, Dim>(q.data())) return 0;
  // Admitted strictly below the bound: one ulp above max_distance² makes it
  // "distance <= max_distance" (an infinite max_distance stays infinite).
  const Scalar bound = next_up(max_distance * max_distance);
  if (k == 1) {
    NearestSet<Scalar> set{bound};
    impl_->run(q.data(), set);
    if (set.position == kNotIndexed) return 0;
    out[0] = Result{impl_->source_of[set.position], set.worst};
    return 1;
  }
  k = std::min(k, size());
  if constexpr (std::is_same_v<Scalar, float>) {
    // The smallest set that holds k (each size costs its full length per
    // insertion).
    const auto small = [&]<std::size_t N>() {
      SmallKnnSet<N> set(k, bound);
      impl_->run(q.data(), set);
      return set.write(out.data(), impl_->source_of.data());
    };
#if ROVE_AVX2_KERNELS
    if (k <= 16 && avx2_enabled()) {
      if (k <= 8) return wide_knn<8>(*impl_, q.data(), k, bound, out.data());
      return wide_knn<16>(*impl_, q.data(), k, bound, out.data());
    }
#endif
    if (k <= 8) return small.template operator()<8>();
    if (k <= 12) return small.template operator()<12>();
    if (k <= 16) return small.template operator()<16>();
    if (k <= 24) return small.template operator()<24>();
    if (k <= 32) return small.template operator()<32>();
  }
  KnnSet<Scalar> set{out.data(), k, impl_->source_of.data()};
  set.worst = bound;
  impl_->run(q.data(), set);
  return set.count;
}

template <int Dim, typename Scalar>
std::span<const std::uint32_t> KdTree<Dim, Scalar>::tree_order() const noexcept {
  if (!impl_) return {};
  return impl_->source_of;
}

template <int Dim, typename Scalar>
std::vector<Neighbor<Scalar>> KdTree<Dim, Scalar>::knn(const Point& q, std::size_t k) const {
  std::vector<Result> out(std::min(k, size()));
  out.resize(knn(q, out.size(), out));
  return out;
}

template <int Dim, typename Scalar>
std::size_t KdTree<Dim, Scalar>::radius(const Point& q, Scalar radius, std::vector<Result>& out,
                                        bool sorted) const {
  ROVE_CHECK_GE(radius, Scalar(0));
  ROVE_CHECK_FINITE(radius);
  out.clear();
  if (empty() || !finite_point<Scalar, Dim>(q.data())) return 0;
  // Points are admitted strictly below the bound; one ulp above radius²
  // makes that "distance <= radius" exactly.
  RadiusSet<Scalar> set{out, impl_->source_of.data(),
                        next_up(radius * radius)};
  impl_->run(q.data(), set);
  if (sorted) sort_neighbors(out);
  return out.size();
}

template <int Dim, typename Scalar>
std::vector<Neighbor<Scalar>> KdTree<Dim, Scalar>::radius(const Point& q, Scalar r) const {
  std::vector<Result> out;
  radius(q, r, out, true);
  return out;
}

template class KdTree<2, float>;
template class KdTree<3, float>;
template class KdTree<2, double>;
template class KdTree<3, double>;

}  // namespace rove
