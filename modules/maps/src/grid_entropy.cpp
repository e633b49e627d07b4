#include "rove/maps/grid_entropy.h"

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <type_traits>
#include <vector>

#include "rove/maps/grid_logodds.h"

namespace rove {

namespace {

// ln 2 as MRPT's float constant.
constexpr float kMaxH = 0.69314718055994531f;

// −p·ln p in float (MRPT's H<float>), 0 at p = 0 and p = 1.
float plogp(float p) { return p == 0.0f || p == 1.0f ? 0.0f : -p * std::log(p); }

// Entropy of every cell value, indexed by the value's unsigned bits (as
// MRPT's table).
template <GridCell Cell>
std::vector<float> entropy_table(EntropyTable table) {
  using Unsigned = std::make_unsigned_t<Cell>;
  constexpr std::size_t kN = std::size_t{1} << (8 * sizeof(Cell));
  const auto& lut = LogOddsLut<Cell>::instance();
  std::vector<float> h(kN);
  for (std::size_t i = 0; i < kN; ++i) {
    const auto value = static_cast<Cell>(static_cast<Unsigned>(i));
    const float p = lut.l2p(value);
    float e = plogp(p) + plogp(1.0f - p);
    if (table == EntropyTable::Mrpt && (i == 0 || i == kN - 1)) e = 0;
    if (e > kMaxH - 1e-4) e = kMaxH;
    h[i] = e;
  }
  return h;
}

}  // namespace

template <GridCell Cell>
GridEntropy grid_entropy(const OccupancyGridT<Cell>& grid, EntropyTable table) {
  using Unsigned = std::make_unsigned_t<Cell>;
  static const std::array<std::vector<float>, 2> tables = {entropy_table<Cell>(EntropyTable::Exact),
                                                           entropy_table<Cell>(EntropyTable::Mrpt)};
  const std::vector<float>& h = tables[table == EntropyTable::Exact ? 0 : 1];
  GridEntropy out;
  double minus_mapped_h = 0;
  for (const Cell c : grid.cells()) {
    const float e = h[static_cast<Unsigned>(c)];
    out.entropy += e;
    if (e < kMaxH - 0.001f) {
      ++out.mapped_cells;
      minus_mapped_h -= e;
    }
  }
  // MRPT's order of operations: I = (−Σ h) / ln 2 + cells.
  out.information = minus_mapped_h / static_cast<double>(kMaxH) + static_cast<double>(out.mapped_cells);
  // MRPT computes the area in float.
  const float res = grid.resolution();
  out.mapped_area = static_cast<double>(static_cast<float>(out.mapped_cells) * res * res);
  if (out.mapped_cells > 0) {
    out.mean_entropy = out.entropy / static_cast<double>(out.mapped_cells);
    out.mean_information = out.information / static_cast<double>(out.mapped_cells);
  }
  return out;
}

template GridEntropy grid_entropy(const OccupancyGridT<std::int8_t>&, EntropyTable);
template GridEntropy grid_entropy(const OccupancyGridT<std::int16_t>&, EntropyTable);

}  // namespace rove
