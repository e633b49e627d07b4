#include "rove/obs/image.h"

#include <string>

#include "rove/core/check.h"
#include "rove/serialization/stl.h"
#include "rove/serialization/version.h"

namespace rove {
namespace {

// width·height·channels·bytes; false on overflow.
bool shape_bytes(std::uint32_t w, std::uint32_t h, std::uint32_t c, PixelType t,
                 std::size_t& out) {
  std::size_t n = 0;
  return !__builtin_mul_overflow(std::size_t{w}, std::size_t{h}, &n) &&
         !__builtin_mul_overflow(n, std::size_t{c}, &n) &&
         !__builtin_mul_overflow(n, bytes_per_sample(t), &out);
}

}  // namespace

std::size_t bytes_per_sample(PixelType t) noexcept {
  switch (t) {
    case PixelType::U8: return 1;
    case PixelType::U16: return 2;
    case PixelType::F32: return 4;
  }
  return 0;
}

Image Image::zeros(std::uint32_t width, std::uint32_t height, std::uint32_t channels,
                   PixelType type) {
  ROVE_CHECK_GE(channels, 1u);
  Image img;
  img.width = width;
  img.height = height;
  img.channels = channels;
  img.pixel_type = type;
  img.data.assign(img.expected_bytes(), 0);
  return img;
}

std::size_t Image::expected_bytes() const {
  ROVE_CHECK_MSG(bytes_per_sample(pixel_type) != 0, "Image: unknown pixel type {}",
                 static_cast<int>(pixel_type));
  std::size_t n = 0;
  ROVE_CHECK_MSG(shape_bytes(width, height, channels, pixel_type, n),
                 "Image: {}x{}x{} overflows the address space", width, height, channels);
  return n;
}

void Image::check() const {
  ROVE_CHECK_MSG(channels >= 1, "Image: channels must be >= 1");
  ROVE_CHECK_MSG(data.size() == expected_bytes(),
                 "Image: {} bytes for a {}x{}x{} image of {}-byte samples (expected {})",
                 data.size(), width, height, channels, bytes_per_sample(pixel_type),
                 expected_bytes());
}

void save(OutArchive& ar, const Image& image) {
  image.check();
  write_version(ar, 1);
  ar.write_scalar(image.width);
  ar.write_scalar(image.height);
  ar.write_scalar(image.channels);
  ar.write_scalar(static_cast<std::uint8_t>(image.pixel_type));
  save(ar, image.data);
}

void load(InArchive& ar, Image& image) {
  read_version(ar, "Image", 1);
  const std::uint64_t at = ar.offset();
  image.width = ar.read_scalar<std::uint32_t>("image width");
  image.height = ar.read_scalar<std::uint32_t>("image height");
  image.channels = ar.read_scalar<std::uint32_t>("image channels");
  const auto type = ar.read_scalar<std::uint8_t>("pixel type");
  if (type > static_cast<std::uint8_t>(PixelType::F32)) {
    ar.fail_at(at, "pixel type", "unknown pixel type " + std::to_string(type));
  }
  image.pixel_type = static_cast<PixelType>(type);
  std::size_t expected = 0;
  if (image.channels == 0 ||
      !shape_bytes(image.width, image.height, image.channels, image.pixel_type, expected)) {
    ar.fail_at(at, "image", "invalid image shape");
  }
  const std::uint64_t at_data = ar.offset();
  load(ar, image.data);
  if (image.data.size() != expected) {
    ar.fail_at(at_data, "image data",
               std::to_string(image.data.size()) + " bytes, the shape needs " +
                   std::to_string(expected));
  }
}

}  // namespace rove
