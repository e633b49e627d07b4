#include "rove/obs/depth_image.h"

#include <cmath>
#include <string>

#include "rove/core/check.h"
#include "rove/serialization/stl.h"
#include "rove/serialization/version.h"

namespace rove {

DepthImage DepthImage::zeros_u16(std::uint32_t width, std::uint32_t height, double scale) {
  DepthImage d;
  d.width = width;
  d.height = height;
  d.scale = scale;
  d.values = std::vector<std::uint16_t>(d.pixel_count(), 0);
  d.check();
  return d;
}

DepthImage DepthImage::zeros_f32(std::uint32_t width, std::uint32_t height, double scale) {
  DepthImage d;
  d.width = width;
  d.height = height;
  d.scale = scale;
  d.values = std::vector<float>(d.pixel_count(), 0.0f);
  d.check();
  return d;
}

void DepthImage::check() const {
  ROVE_CHECK_MSG(std::isfinite(scale) && scale > 0.0,
                 "DepthImage: scale {} (stored units per meter) must be finite and > 0", scale);
  const std::size_t n = std::visit([](const auto& v) { return v.size(); }, values);
  ROVE_CHECK_MSG(n == pixel_count(), "DepthImage: {} values for a {}x{} image", n, width, height);
}

double DepthImage::meters(std::uint32_t u, std::uint32_t v) const {
  check();
  ROVE_CHECK_LT(u, width);
  ROVE_CHECK_LT(v, height);
  const std::size_t i = static_cast<std::size_t>(v) * width + u;
  return std::visit([&](const auto& vals) { return static_cast<double>(vals[i]) / scale; },
                    values);
}

void DepthImage::set_meters(std::uint32_t u, std::uint32_t v, double meters) {
  check();
  ROVE_CHECK_LT(u, width);
  ROVE_CHECK_LT(v, height);
  const std::size_t i = static_cast<std::size_t>(v) * width + u;
  if (auto* u16 = std::get_if<std::vector<std::uint16_t>>(&values)) {
    const double units = std::round(meters * scale);
    ROVE_CHECK_MSG(std::isfinite(units) && units >= 0.0 && units <= 65535.0,
                   "DepthImage: {} m is {} units, outside a 16-bit image's [0, 65535]", meters,
                   units);
    (*u16)[i] = static_cast<std::uint16_t>(units);
  } else {
    std::get<std::vector<float>>(values)[i] = static_cast<float>(meters * scale);
  }
}

void save(OutArchive& ar, const DepthImage& d) {
  d.check();
  write_version(ar, 1);
  ar.write_scalar(d.width);
  ar.write_scalar(d.height);
  ar.write_scalar(d.scale);
  const bool is_float = std::holds_alternative<std::vector<float>>(d.values);
  ar.write_scalar(static_cast<std::uint8_t>(is_float ? 1 : 0));
  std::visit([&](const auto& v) { save(ar, v); }, d.values);
}

void load(InArchive& ar, DepthImage& d) {
  read_version(ar, "DepthImage", 1);
  const std::uint64_t at = ar.offset();
  d.width = ar.read_scalar<std::uint32_t>("depth width");
  d.height = ar.read_scalar<std::uint32_t>("depth height");
  d.scale = ar.read_scalar<double>("depth scale");
  if (!(std::isfinite(d.scale) && d.scale > 0.0)) {
    ar.fail_at(at, "depth scale", "scale must be finite and > 0");
  }
  const auto kind = ar.read_scalar<std::uint8_t>("depth type");
  const std::uint64_t at_values = ar.offset();
  if (kind == 0) {
    std::vector<std::uint16_t> v;
    load(ar, v);
    d.values = std::move(v);
  } else if (kind == 1) {
    std::vector<float> v;
    load(ar, v);
    d.values = std::move(v);
  } else {
    ar.fail_at(at_values - 1, "depth type", "unknown depth sample type " + std::to_string(kind));
  }
  const std::size_t n = std::visit([](const auto& v) { return v.size(); }, d.values);
  if (n != d.pixel_count()) {
    ar.fail_at(at_values, "depth values",
               std::to_string(n) + " values for a " + std::to_string(d.width) + "x" +
                   std::to_string(d.height) + " image");
  }
}

}  // namespace rove
