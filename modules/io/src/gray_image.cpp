#include "rove/io/gray_image.h"
#include "rove/io/frame_images.h"

#include <png.h>
#include <zlib.h>

#include <algorithm>
#include <bit>
#include <cctype>
#include <csetjmp>
#include <cstdio>
#include <cstring>
#include <memory>

#include <fmt/format.h>

#include "rove/core/check.h"
#include "rove/core/error.h"
#include "rove/core/files.h"
#include "rove/core/memory_budget.h"
#include "rove/io/file_bytes.h"

namespace rove {
namespace {

[[noreturn]] void fail(std::string_view source, std::uint64_t offset, std::string_view field,
                       std::string problem) {
  throw ParseError({std::string(source), std::nullopt, offset, std::string(field)},
                   std::move(problem));
}

void check_declared_size(std::string_view source, std::uint64_t offset, std::uint64_t w,
                         std::uint64_t h, const ImageLimits& limits) {
  if (w == 0 || h == 0) fail(source, offset, "size", fmt::format("empty image ({} x {})", w, h));
  if (w > limits.max_side || h > limits.max_side) {
    fail(source, offset, "size",
         fmt::format("declares {} x {} pixels, a side above the limit of {}", w, h,
                     limits.max_side));
  }
  if (w * h > limits.max_pixels) {
    fail(source, offset, "size",
         fmt::format("declares {} x {} = {} pixels, above the limit of {}", w, h, w * h,
                     limits.max_pixels));
  }
  // The decoded image takes a byte per pixel, and the grid made from it as
  // much again: refuse before allocating what the machine cannot hold.
  check_memory_budget(checked_bytes(w * h, 2),
                      fmt::format("{}: {} \u00d7 {} pixels (the image and its grid)", source, w, h));
}

// ---------------------------------------------------------------- PNG ----
// libpng reports errors with longjmp. The functions that call setjmp below
// hold no C++ object with a destructor, so jumping back skips nothing; all
// C++ state lives in the callers.

struct PngInput {
  const std::uint8_t* data = nullptr;
  std::size_t size = 0;
  std::size_t pos = 0;
  bool ran_out = false;
  char message[256] = {};
};

void png_read_callback(png_structp png, png_bytep out, std::size_t n) {
  auto* in = static_cast<PngInput*>(png_get_io_ptr(png));
  if (n > in->size - in->pos) {
    in->ran_out = true;
    png_error(png, "unexpected end of data");
  }
  std::memcpy(out, in->data + in->pos, n);
  in->pos += n;
}

void png_error_callback(png_structp png, png_const_charp message) {
  auto* msg = static_cast<char*>(png_get_error_ptr(png));
  std::snprintf(msg, 256, "%s", message);
  png_longjmp(png, 1);
}

void png_warning_callback(png_structp, png_const_charp) {}

struct PngHeader {
  png_uint_32 width = 0, height = 0;
  int bit_depth = 0, color_type = 0, interlace = 0, channels_in = 0, channels_out = 0;
  std::size_t rowbytes_out = 0;
};

// What the decoded samples become: 8-bit gray or colour channels as stored
// (gray images), 8-bit RGB (colour frames), or the 16-bit samples of a
// single-channel image in native byte order (depth frames; other images are
// left as they are for the caller to refuse).
enum class PngTarget { Gray8, Rgb8, Native16 };

bool png_read_header(png_structp png, png_infop info, PngHeader* h, PngTarget target = PngTarget::Gray8) {
  if (setjmp(png_jmpbuf(png))) return false;
  png_read_info(png, info);
  h->width = png_get_image_width(png, info);
  h->height = png_get_image_height(png, info);
  h->bit_depth = png_get_bit_depth(png, info);
  h->color_type = png_get_color_type(png, info);
  h->interlace = png_get_interlace_type(png, info);
  h->channels_in = png_get_channels(png, info);
  if (target == PngTarget::Native16) {
    if constexpr (std::endian::native == std::endian::little) {
      if (h->bit_depth == 16) png_set_swap(png);
    }
  } else if (h->bit_depth == 16) {
    png_set_strip_16(png);
  }
  if (h->color_type == PNG_COLOR_TYPE_PALETTE) png_set_palette_to_rgb(png);
  if (h->color_type == PNG_COLOR_TYPE_GRAY && h->bit_depth < 8) {
    png_set_expand_gray_1_2_4_to_8(png);
  }
  if (target == PngTarget::Rgb8) {
    if ((h->color_type & PNG_COLOR_MASK_COLOR) == 0) png_set_gray_to_rgb(png);
    if ((h->color_type & PNG_COLOR_MASK_ALPHA) != 0) png_set_strip_alpha(png);
  }
  if (h->interlace != PNG_INTERLACE_NONE) (void)png_set_interlace_handling(png);
  png_read_update_info(png, info);
  h->channels_out = png_get_channels(png, info);
  h->rowbytes_out = png_get_rowbytes(png, info);
  return true;
}

// Non-interlaced: one row at a time into `row`, converted into `gray`.
bool png_read_rows_progressive(png_structp png, png_infop info, const PngHeader* h,
                               std::uint8_t* row, std::uint8_t* gray) {
  if (setjmp(png_jmpbuf(png))) return false;
  const int c = h->channels_out;
  for (png_uint_32 y = 0; y < h->height; ++y) {
    png_read_row(png, row, nullptr);
    std::uint8_t* g = gray + static_cast<std::size_t>(y) * h->width;
    for (png_uint_32 x = 0; x < h->width; ++x) {
      const std::uint8_t* p = row + static_cast<std::size_t>(x) * static_cast<std::size_t>(c);
      // ROS map_server: the integer average of the color channels, alpha ignored.
      g[x] = c >= 3 ? static_cast<std::uint8_t>((p[0] + p[1] + p[2]) / 3) : p[0];
    }
  }
  png_read_end(png, info);
  return true;
}

bool png_read_whole(png_structp png, png_infop info, png_bytepp rows) {
  if (setjmp(png_jmpbuf(png))) return false;
  png_read_image(png, rows);
  png_read_end(png, info);
  return true;
}

struct PngReadGuard {
  png_structp png = nullptr;
  png_infop info = nullptr;
  ~PngReadGuard() { png_destroy_read_struct(&png, &info, nullptr); }
};

struct PngOutput {
  std::vector<std::uint8_t>* bytes = nullptr;
};

void png_write_callback(png_structp png, png_bytep data, std::size_t n) {
  auto* out = static_cast<PngOutput*>(png_get_io_ptr(png));
  out->bytes->insert(out->bytes->end(), data, data + n);
}
void png_flush_callback(png_structp) {}

bool png_write_all(png_structp png, png_infop info, const GrayImage* image,
                   const std::vector<png_color>* palette, bool fast) {
  if (setjmp(png_jmpbuf(png))) return false;
  png_set_IHDR(png, info, image->width, image->height, 8,
               palette->empty() ? PNG_COLOR_TYPE_GRAY : PNG_COLOR_TYPE_PALETTE,
               PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  if (!palette->empty()) {
    png_set_PLTE(png, info, palette->data(), static_cast<int>(palette->size()));
  }
  if (fast) {
    // Maps and pictures are mostly one flat color: libpng's per-row filter
    // search costs more than it saves there, and run-length deflate finds
    // the long runs of background in a fraction of a match search's time.
    png_set_filter(png, PNG_FILTER_TYPE_BASE, PNG_FILTER_NONE);
    png_set_compression_level(png, 1);
    png_set_compression_strategy(png, Z_RLE);
  }
  png_write_info(png, info);
  for (std::uint32_t y = 0; y < image->height; ++y) {
    png_write_row(png, const_cast<png_bytep>(image->pixels.data() +
                                             static_cast<std::size_t>(y) * image->width));
  }
  png_write_end(png, nullptr);
  return true;
}

struct PngWriteGuard {
  png_structp png = nullptr;
  png_infop info = nullptr;
  ~PngWriteGuard() { png_destroy_write_struct(&png, &info); }
};

void check_image(const GrayImage& image) {
  ROVE_CHECK_GT(image.width, 0u);
  ROVE_CHECK_GT(image.height, 0u);
  ROVE_CHECK_EQ(image.pixels.size(), static_cast<std::size_t>(image.width) * image.height);
}

// ---------------------------------------------------------------- PGM ----

class PgmCursor {
 public:
  PgmCursor(std::span<const std::uint8_t> d, std::string_view source) : d_(d), source_(source) {}

  std::size_t pos() const { return pos_; }
  std::size_t remaining() const { return d_.size() - pos_; }
  const std::uint8_t* here() const { return d_.data() + pos_; }
  void advance(std::size_t n) { pos_ += n; }

  // Whitespace and `#` comments (to the end of the line).
  void skip_space() {
    while (pos_ < d_.size()) {
      const auto c = d_[pos_];
      if (c == '#') {
        while (pos_ < d_.size() && d_[pos_] != '\n' && d_[pos_] != '\r') ++pos_;
      } else if (std::isspace(c)) {
        ++pos_;
      } else {
        break;
      }
    }
  }

  // A decimal number after optional space/comments; at most `max`.
  std::uint64_t number(std::string_view field, std::uint64_t max) {
    skip_space();
    const std::size_t start = pos_;
    if (pos_ >= d_.size()) fail(source_, start, field, "unexpected end of data");
    if (!std::isdigit(d_[pos_])) {
      fail(source_, start, field,
           fmt::format("expected a decimal number, found byte 0x{:02x}", d_[pos_]));
    }
    std::uint64_t v = 0;
    while (pos_ < d_.size() && std::isdigit(d_[pos_])) {
      v = v * 10 + (d_[pos_] - '0');
      if (v > max) fail(source_, start, field, fmt::format("value above {}", max));
      ++pos_;
    }
    if (pos_ < d_.size() && !std::isspace(d_[pos_]) && d_[pos_] != '#') {
      fail(source_, pos_, field, fmt::format("unexpected byte 0x{:02x} after the number", d_[pos_]));
    }
    return v;
  }

 private:
  std::span<const std::uint8_t> d_;
  std::string_view source_;
  std::size_t pos_ = 0;
};

// A PGM header after its two magic bytes (checked by the caller).
struct PgmHeader {
  std::uint64_t width = 0, height = 0, maxval = 0;
  std::size_t size_at = 0;  // offset of the width
};

PgmHeader read_pgm_header(PgmCursor& c, std::string_view source) {
  c.advance(2);
  if (c.remaining() > 0 && !std::isspace(*c.here()) && *c.here() != '#') {
    fail(source, 2, "magic", "expected whitespace after the magic number");
  }
  PgmHeader h;
  h.size_at = c.pos();
  h.width = c.number("width", std::uint64_t{1} << 32);
  h.height = c.number("height", std::uint64_t{1} << 32);
  h.maxval = c.number("maxval", 65535);
  if (h.maxval == 0) fail(source, c.pos(), "maxval", "maxval must be 1 to 65535, got 0");
  return h;
}

// A PNG opened for decoding: signature checked, decoder created with the
// limits, header read for `target` and checked against the limits and
// against what the bytes left can hold.
class PngDecoder {
 public:
  PngDecoder(std::span<const std::uint8_t> data, std::string_view source, const ImageLimits& limits,
             PngTarget target)
      : source_(source) {
    static constexpr std::uint8_t kSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    if (data.size() < 8 || std::memcmp(data.data(), kSignature, 8) != 0) {
      const bool prefix =
          data.size() < 8 && std::equal(data.begin(), data.end(), std::begin(kSignature));
      fail(source, 0, "signature",
           prefix ? "truncated PNG: incomplete signature" : "not a PNG file (bad signature)");
    }
    in_.data = data.data();
    in_.size = data.size();
    g_.png = png_create_read_struct(PNG_LIBPNG_VER_STRING, in_.message, png_error_callback,
                                    png_warning_callback);
    if (g_.png != nullptr) g_.info = png_create_info_struct(g_.png);
    if (g_.png == nullptr || g_.info == nullptr) {
      throw IoError(std::string(source), "cannot create the PNG decoder");
    }
    png_set_read_fn(g_.png, &in_, png_read_callback);
    png_set_user_limits(g_.png, limits.max_side, limits.max_side);
    png_set_chunk_malloc_max(g_.png, 8u << 20);
    png_set_chunk_cache_max(g_.png, 1000);
    if (!png_read_header(g_.png, g_.info, &h_, target)) fail_at("header");
    check_declared_size(source, 16, h_.width, h_.height, limits);
    // Deflate cannot compress better than 1032:1, so the raw scanlines the
    // header declares must fit in the bytes that remain (times that ratio).
    const std::uint64_t raw_row =
        (static_cast<std::uint64_t>(h_.width) * static_cast<unsigned>(h_.bit_depth * h_.channels_in) + 7) / 8 + 1;
    const std::uint64_t raw = raw_row * h_.height;
    const std::uint64_t left = data.size() - in_.pos;
    if (raw > 1032 * left + 1032) {
      fail(source, 16, "size",
           fmt::format("declares {} x {} pixels ({} bytes of scanlines), more than the {} bytes "
                       "left in the file can hold",
                       h_.width, h_.height, raw, left));
    }
  }
  const PngHeader& header() const { return h_; }
  png_structp png() const { return g_.png; }
  png_infop info() const { return g_.info; }
  // libpng stopped: truncated data or its own message, at the byte reached.
  [[noreturn]] void fail_at(std::string_view field) const {
    fail(source_, in_.pos, field,
         in_.ran_out ? std::string("truncated PNG: unexpected end of data")
                     : fmt::format("invalid PNG: {}", in_.message));
  }
  // Every row (interlaced or not) into one buffer of rowbytes × height.
  std::vector<std::uint8_t> read_all() {
    std::vector<std::uint8_t> buf(h_.rowbytes_out * h_.height);
    std::vector<png_bytep> rows(h_.height);
    for (std::uint32_t y = 0; y < h_.height; ++y) rows[y] = buf.data() + h_.rowbytes_out * y;
    if (!png_read_whole(g_.png, g_.info, rows.data())) fail_at("image data");
    return buf;
  }

 private:
  std::string_view source_;
  PngInput in_;
  PngReadGuard g_;
  PngHeader h_;
};

}  // namespace

ImageFormat image_format_from_path(std::string_view path) {
  std::string ext;
  const auto dot = path.find_last_of('.');
  if (dot != std::string_view::npos) ext = std::string(path.substr(dot + 1));
  for (auto& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (ext == "png") return ImageFormat::Png;
  if (ext == "pgm") return ImageFormat::Pgm;
  throw InvalidArgument(
      fmt::format("{}: unknown image extension (expected .png or .pgm)", path));
}

GrayImage decode_png(std::span<const std::uint8_t> data, std::string_view source,
                     const ImageLimits& limits) {
  PngDecoder d(data, source, limits, PngTarget::Gray8);
  const PngHeader& h = d.header();
  GrayImage img;
  img.width = h.width;
  img.height = h.height;
  img.pixels.resize(static_cast<std::size_t>(h.width) * h.height);
  if (h.interlace == PNG_INTERLACE_NONE) {
    std::vector<std::uint8_t> row(h.rowbytes_out);
    if (!png_read_rows_progressive(d.png(), d.info(), &h, row.data(), img.pixels.data())) {
      d.fail_at("image data");
    }
    return img;
  }
  const std::vector<std::uint8_t> buf = d.read_all();
  const int c = h.channels_out;
  for (std::uint32_t y = 0; y < h.height; ++y) {
    for (std::uint32_t x = 0; x < h.width; ++x) {
      const std::uint8_t* p = buf.data() + h.rowbytes_out * y + static_cast<std::size_t>(x) * static_cast<std::size_t>(c);
      img.pixels[static_cast<std::size_t>(y) * h.width + x] =
          c >= 3 ? static_cast<std::uint8_t>((p[0] + p[1] + p[2]) / 3) : p[0];
    }
  }
  return img;
}

namespace {

// The samples of a PNG decoded for `target`, rows top to bottom: 3 bytes a
// pixel for Rgb8, 2 (native order) for a 16-bit single-channel Native16;
// `h` says what the file holds. For Native16 an image of another kind is
// refused by `refuse(h)` before its rows are decoded.
template <typename Refuse>
std::vector<std::uint8_t> decode_png_samples(std::span<const std::uint8_t> data, std::string_view source,
                                             const ImageLimits& limits, PngTarget target,
                                             PngHeader& h, Refuse&& refuse) {
  PngDecoder d(data, source, limits, target);
  h = d.header();
  if (target == PngTarget::Native16) refuse(h);
  check_memory_budget(checked_bytes(static_cast<std::uint64_t>(h.rowbytes_out) * h.height, 1),
                      fmt::format("{}: {} \u00d7 {} pixels", source, h.width, h.height));
  return d.read_all();
}

// "8-bit with 3 channel(s)" for the refusal of a depth image.
[[noreturn]] void refuse_depth(std::string_view source, std::uint64_t offset, unsigned bits,
                               unsigned channels) {
  fail(source, offset, "depth image",
       fmt::format("a depth image must be 16-bit with one channel; this one is {}-bit with {} "
                   "channel(s) (an 8-bit depth image has lost its range)",
                   bits, channels));
}

}  // namespace

ColorImage8 decode_color_image(std::span<const std::uint8_t> data, std::string_view source,
                               const ImageLimits& limits) {
  if (data.size() >= 2 && data[0] == 'P' && data[1] >= '1' && data[1] <= '7') {
    fail(source, 0, "magic", "a colour image must be a PNG file; this is a Netpbm file");
  }
  PngHeader h;
  std::vector<std::uint8_t> rgb =
      decode_png_samples(data, source, limits, PngTarget::Rgb8, h, [](const PngHeader&) {});
  ROVE_CHECK_EQ(h.rowbytes_out, std::size_t{3} * h.width);
  return {h.width, h.height, std::move(rgb)};
}

DepthImage16 decode_depth_image(std::span<const std::uint8_t> data, std::string_view source,
                                const ImageLimits& limits) {
  DepthImage16 out;
  if (!data.empty() && data[0] == 'P') {
    if (data.size() < 2) fail(source, 0, "magic", "truncated PGM: no magic number");
    if (data[1] == '2') fail(source, 0, "magic", "a depth PGM must be binary (P5), not ASCII (P2)");
    if (data[1] != '5') fail(source, 0, "magic", "not a PGM depth image (expected P5)");
    PgmCursor c(data, source);
    const PgmHeader ph = read_pgm_header(c, source);
    const std::uint64_t w = ph.width, h = ph.height, maxval = ph.maxval;
    if (maxval < 256) refuse_depth(source, ph.size_at, 8, 1);
    check_declared_size(source, ph.size_at, w, h, limits);
    if (c.remaining() == 0) fail(source, c.pos(), "maxval", "truncated PGM: no image data");
    c.advance(1);
    const std::uint64_t n = w * h;
    if (2 * n > c.remaining()) {
      fail(source, c.pos(), "image data",
           fmt::format("truncated PGM: {} x {} pixels need {} bytes, {} remain", w, h, 2 * n,
                       c.remaining()));
    }
    out.width = static_cast<std::uint32_t>(w);
    out.height = static_cast<std::uint32_t>(h);
    out.values.resize(n);
    const std::uint8_t* p = c.here();
    for (std::uint64_t i = 0; i < n; ++i) {
      const auto v = static_cast<std::uint16_t>((p[2 * i] << 8) | p[2 * i + 1]);
      if (v > maxval) {
        fail(source, c.pos() + 2 * i, "image data", fmt::format("sample {} above maxval {}", v, maxval));
      }
      out.values[i] = v;
    }
    return out;
  }
  PngHeader h;
  const std::vector<std::uint8_t> bytes =
      decode_png_samples(data, source, limits, PngTarget::Native16, h, [&](const PngHeader& hh) {
        if (hh.bit_depth != 16 || hh.color_type != PNG_COLOR_TYPE_GRAY) {
          refuse_depth(source, 16, static_cast<unsigned>(hh.bit_depth),
                       static_cast<unsigned>(hh.channels_in));
        }
      });
  ROVE_CHECK_EQ(h.rowbytes_out, std::size_t{2} * h.width);
  out.width = h.width;
  out.height = h.height;
  out.values.resize(static_cast<std::size_t>(h.width) * h.height);
  std::memcpy(out.values.data(), bytes.data(), bytes.size());
  return out;
}

ColorImage8 read_color_image(const std::string& path, const ImageLimits& limits) {
  const auto bytes = read_file_bytes(path, 0, "colour image");
  return decode_color_image(bytes, path, limits);
}

DepthImage16 read_depth_image(const std::string& path, const ImageLimits& limits) {
  const auto bytes = read_file_bytes(path, 0, "depth image");
  return decode_depth_image(bytes, path, limits);
}

GrayImage decode_pgm(std::span<const std::uint8_t> data, std::string_view source,
                     const ImageLimits& limits) {
  if (data.size() < 2) fail(source, 0, "magic", "truncated PGM: no magic number");
  if (data[0] != 'P' || (data[1] != '5' && data[1] != '2')) {
    fail(source, 0, "magic", "not a PGM file (expected P5 or P2)");
  }
  const bool binary = data[1] == '5';
  PgmCursor c(data, source);
  const PgmHeader ph = read_pgm_header(c, source);
  const std::uint64_t w = ph.width, h = ph.height, maxval = ph.maxval;
  check_declared_size(source, ph.size_at, w, h, limits);
  const std::uint64_t n = w * h;
  GrayImage img;
  const auto scale = [maxval](std::uint64_t v) {
    return static_cast<std::uint8_t>(maxval == 255 ? v : (v * 255 + maxval / 2) / maxval);
  };
  if (binary) {
    // Exactly one whitespace byte separates the header from the samples.
    if (c.remaining() == 0) fail(source, c.pos(), "maxval", "truncated PGM: no image data");
    c.advance(1);
    const std::uint64_t bps = maxval < 256 ? 1 : 2;
    if (n * bps > c.remaining()) {
      fail(source, c.pos(), "image data",
           fmt::format("truncated PGM: {} x {} pixels need {} bytes, {} remain", w, h, n * bps,
                       c.remaining()));
    }
    img.width = static_cast<std::uint32_t>(w);
    img.height = static_cast<std::uint32_t>(h);
    img.pixels.resize(n);
    const std::uint8_t* p = c.here();
    for (std::uint64_t i = 0; i < n; ++i) {
      const std::uint64_t v = bps == 1 ? p[i] : (std::uint64_t{p[2 * i]} << 8) | p[2 * i + 1];
      if (v > maxval) {
        fail(source, c.pos() + i * bps, "image data",
             fmt::format("sample {} above maxval {}", v, maxval));
      }
      img.pixels[i] = scale(v);
    }
    return img;
  }
  // P2: every sample takes at least one digit and one separator.
  if (2 * n - 1 > c.remaining()) {
    fail(source, c.pos(), "image data",
         fmt::format("truncated PGM: {} x {} samples cannot fit in the {} bytes that remain", w,
                     h, c.remaining()));
  }
  img.width = static_cast<std::uint32_t>(w);
  img.height = static_cast<std::uint32_t>(h);
  img.pixels.resize(n);
  for (std::uint64_t i = 0; i < n; ++i) {
    const std::size_t at = c.pos();
    const std::uint64_t v = c.number("image data", 65535);
    if (v > maxval) {
      fail(source, at, "image data", fmt::format("sample {} above maxval {}", v, maxval));
    }
    img.pixels[i] = scale(v);
  }
  return img;
}

GrayImage decode_gray_image(std::span<const std::uint8_t> data, std::string_view source,
                            const ImageLimits& limits) {
  if (!data.empty() && data[0] == 0x89) return decode_png(data, source, limits);
  if (!data.empty() && data[0] == 'P') return decode_pgm(data, source, limits);
  fail(source, 0, "magic", "neither a PNG nor a PGM file");
}

GrayImage read_gray_image(const std::string& path, const ImageLimits& limits) {
  const auto bytes = read_file_bytes(path, 0, "map image");
  return decode_gray_image(bytes, path, limits);
}

std::vector<std::uint8_t> encode_png(const GrayImage& image, const PngEncoding& encoding) {
  check_image(image);
  ROVE_CHECK_LE(encoding.palette.size(), std::size_t{256});
  std::vector<png_color> palette;
  for (const auto& c : encoding.palette) palette.push_back({c.r, c.g, c.b});
  if (!palette.empty()) {
    const auto top = *std::max_element(image.pixels.begin(), image.pixels.end());
    ROVE_CHECK_MSG(top < palette.size(), "pixel value {} is not an index into a palette of {} colors",
                   top, palette.size());
  }
  std::vector<std::uint8_t> bytes;
  PngOutput out{&bytes};
  char message[256] = {};
  PngWriteGuard g;
  g.png = png_create_write_struct(PNG_LIBPNG_VER_STRING, message, png_error_callback,
                                  png_warning_callback);
  if (g.png != nullptr) g.info = png_create_info_struct(g.png);
  if (g.png == nullptr || g.info == nullptr) throw IoError("<png>", "cannot create the PNG encoder");
  png_set_write_fn(g.png, &out, png_write_callback, png_flush_callback);
  if (!png_write_all(g.png, g.info, &image, &palette, encoding.fast)) {
    throw IoError("<png>", fmt::format("PNG encoding failed: {}", message));
  }
  return bytes;
}

std::vector<std::uint8_t> encode_pgm(const GrayImage& image) {
  check_image(image);
  const std::string header = fmt::format("P5\n{} {}\n255\n", image.width, image.height);
  std::vector<std::uint8_t> bytes(header.begin(), header.end());
  bytes.insert(bytes.end(), image.pixels.begin(), image.pixels.end());
  return bytes;
}

void write_gray_image(const std::string& path, const GrayImage& image, ImageFormat format) {
  write_file_bytes(path, format == ImageFormat::Png ? encode_png(image) : encode_pgm(image));
}

void write_png(const std::string& path, const GrayImage& image, const PngEncoding& encoding) {
  write_file_bytes(path, encode_png(image, encoding));
}

}  // namespace rove
