#pragma once
/// \file
/// Integer log-odds cells of occupancy grids and the lookup tables that turn
/// them into probabilities and back, with MRPT's scaling
/// (CLogOddsGridMapLUT), so that cell values agree with MRPT bit for bit.
///
/// A cell stores L = round(16 · ln(p / (1 − p))) clamped to the type's range
/// [−max, +max], where p is the probability that the cell is FREE (MRPT's
/// convention: 1 = certainly free, 0 = certainly occupied, 0.5 = unknown).

#include <array>
#include <cstddef>
#include <cstdint>
#include <type_traits>
#include <vector>

namespace rove {

/// The cell types an occupancy grid supports.
template <typename Cell>
concept GridCell = std::same_as<Cell, std::int8_t> || std::same_as<Cell, std::int16_t>;

/// Range and table sizes of a log-odds cell type.
template <GridCell Cell>
struct LogOddsTraits {
  /// Largest cell value (certainly free).
  static constexpr int kMax = std::is_same_v<Cell, std::int8_t> ? 127 : 32767;
  /// Smallest cell value (certainly occupied); the type's most negative value
  /// (−128 / −32768) is never produced and reads as kMin.
  static constexpr int kMin = -kMax;
  /// Entries of the probability-to-log-odds table minus one.
  static constexpr int kP2LSize = kMax;
  /// Log-odds scale: a cell holds 16 · ln(p / (1 − p)).
  static constexpr double kScale = 16.0;
};

/// Lookup tables between cells and probabilities (immutable after
/// construction; one shared instance per cell type, see instance()).
/// Thread-safety: safe for concurrent reads.
template <GridCell Cell>
class LogOddsLut {
 public:
  using Traits = LogOddsTraits<Cell>;

  /// The shared tables for this cell type.
  static const LogOddsLut& instance();

  /// Probability of "free" of a cell value: 1 / (1 + exp(−L/16)), as float.
  float l2p(Cell l) const noexcept {
    const int i = l < Traits::kMin ? Traits::kMin : static_cast<int>(l);
    return l2p_[static_cast<std::size_t>(i - Traits::kMin)];
  }
  /// l2p scaled to [0, 255] and truncated (MRPT's l2p_255).
  std::uint8_t l2p_255(Cell l) const noexcept {
    const int i = l < Traits::kMin ? Traits::kMin : static_cast<int>(l);
    return l2p_255_[static_cast<std::size_t>(i - Traits::kMin)];
  }
  /// Cell value of a probability of "free" p ∈ [0, 1] (MRPT's p2l: the
  /// table entry at floor(p · kP2LSize)). Precondition: 0 <= p <= 1 (values
  /// outside are clamped; NaN reads as 0.5).
  Cell p2l(float p) const noexcept {
    if (!(p >= 0.0f)) p = (p < 0.0f) ? 0.0f : 0.5f;
    if (p > 1.0f) p = 1.0f;
    return p2l_[static_cast<std::size_t>(p * static_cast<float>(Traits::kP2LSize))];
  }

 private:
  LogOddsLut();
  std::vector<float> l2p_;
  std::vector<std::uint8_t> l2p_255_;
  std::vector<Cell> p2l_;
};

extern template class LogOddsLut<std::int8_t>;
extern template class LogOddsLut<std::int16_t>;

}  // namespace rove
