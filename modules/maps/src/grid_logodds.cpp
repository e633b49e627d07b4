#include "rove/maps/grid_logodds.h"

#include <algorithm>
#include <cmath>

namespace rove {

template <GridCell Cell>
LogOddsLut<Cell>::LogOddsLut() {
  const std::size_t n = static_cast<std::size_t>(Traits::kMax - Traits::kMin + 1);
  l2p_.resize(n);
  l2p_255_.resize(n);
  const double inv_scale = 1.0 / Traits::kScale;
  for (int i = Traits::kMin; i <= Traits::kMax; ++i) {
    // Evaluated as MRPT does: in double, then rounded to float.
    const float f = static_cast<float>(1.0 / (1.0 + std::exp(-i * inv_scale)));
    const auto idx = static_cast<std::size_t>(i - Traits::kMin);
    l2p_[idx] = f;
    l2p_255_[idx] = static_cast<std::uint8_t>(f * 255.0f);
  }
  p2l_.resize(static_cast<std::size_t>(Traits::kP2LSize) + 1);
  const double step = 1.0 / Traits::kP2LSize;
  for (int j = 0; j <= Traits::kP2LSize; ++j) {
    const double p = std::min(1.0 - 1e-14, std::max(1e-14, j * step));
    const double logodd = std::log(p) - std::log(1.0 - p);
    const int l = std::clamp(static_cast<int>(std::lrint(logodd * Traits::kScale)), Traits::kMin,
                             Traits::kMax);
    p2l_[static_cast<std::size_t>(j)] = static_cast<Cell>(l);
  }
}

template <GridCell Cell>
const LogOddsLut<Cell>& LogOddsLut<Cell>::instance() {
  static const LogOddsLut lut;
  return lut;
}

template class LogOddsLut<std::int8_t>;
template class LogOddsLut<std::int16_t>;

}  // namespace rove
