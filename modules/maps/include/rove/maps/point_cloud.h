#pragma once
/// \file
/// PointCloud: a plain container of 3D points with optional per-point
/// channels (color, intensity, normal). It is the value type that files
/// (PCD, PLY), filters (voxel grid, pass-through) and registration exchange;
/// PointMap (point_map.h) adds MRPT's insertion/likelihood semantics and a
/// cached KD-tree on top of it.
///
/// Storage, and why:
///  - coordinates are `float`, meters. A nearest-neighbour search (the inner
///    loop of ICP) is bound by memory traffic; float halves it against
///    double. PCD and PLY files store float32 almost always, so reading and
///    writing round-trips exactly, and MRPT's point maps and PCL's clouds
///    both store float, so results agree with the peers bit for bit.
///    Sums (centroids, transforms) are evaluated in double and rounded once.
///  - points are contiguous `Eigen::Vector3f` (array of structures, 12 bytes
///    per point, no padding): a distance evaluation reads the three
///    coordinates of one point together, one cache line rather than the
///    three that MRPT's separate xs/ys/zs vectors touch.
///  - each optional channel is its own contiguous vector, present for all
///    points or for none: searches never touch them.
///
/// A PointCloud may hold non-finite points (PCL's "not dense" clouds, as
/// PCD files can carry them); algorithms that cannot use them skip them and
/// say so in their documentation. Not thread-safe for concurrent mutation;
/// concurrent const access is safe.

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include <Eigen/Core>

namespace rove {

/// An 8-bit RGB color (PCL's rgb, PLY's red/green/blue).
struct Rgb8 {
  std::uint8_t r = 0;  ///< red, 0..255
  std::uint8_t g = 0;  ///< green, 0..255
  std::uint8_t b = 0;  ///< blue, 0..255
  friend bool operator==(const Rgb8&, const Rgb8&) = default;
};

/// Which optional channels a cloud carries (bit set).
enum class PointChannels : std::uint8_t {
  None = 0,
  Color = 1,      ///< Rgb8 per point
  Intensity = 2,  ///< float per point (sensor units)
  Normal = 4,     ///< unit normal (nx, ny, nz) per point
};
constexpr PointChannels operator|(PointChannels a, PointChannels b) noexcept {
  return static_cast<PointChannels>(static_cast<std::uint8_t>(a) | static_cast<std::uint8_t>(b));
}
constexpr PointChannels operator&(PointChannels a, PointChannels b) noexcept {
  return static_cast<PointChannels>(static_cast<std::uint8_t>(a) & static_cast<std::uint8_t>(b));
}
/// True when every channel of `wanted` is in `have`.
constexpr bool has_all(PointChannels have, PointChannels wanted) noexcept {
  return (have & wanted) == wanted;
}

/// Axis-aligned bounding box, meters. Empty when min > max on any axis.
struct BoundingBox3 {
  Eigen::Vector3f min = Eigen::Vector3f::Constant(1.0f);
  Eigen::Vector3f max = Eigen::Vector3f::Constant(-1.0f);
  /// True when it contains no point (the box of an empty cloud).
  bool empty() const noexcept { return (min.array() > max.array()).any(); }
  /// Whether p lies inside or on the box.
  bool contains(const Eigen::Vector3f& p) const noexcept {
    return (p.array() >= min.array()).all() && (p.array() <= max.array()).all();
  }
  friend bool operator==(const BoundingBox3&, const BoundingBox3&) = default;
};

/// A cloud of 3D points (meters) with optional color, intensity and normal
/// channels. Invariant: every enabled channel has size() entries.
class PointCloud {
 public:
  PointCloud() = default;
  /// A cloud holding `points`, no channels.
  explicit PointCloud(std::vector<Eigen::Vector3f> points) : points_(std::move(points)) {}

  /// Number of points.
  std::size_t size() const noexcept { return points_.size(); }
  /// True when there is no point.
  bool empty() const noexcept { return points_.empty(); }
  /// Removes every point; the set of enabled channels is kept.
  void clear() noexcept;
  /// Reserves room for n points in the coordinates and every enabled channel.
  void reserve(std::size_t n);
  /// Resizes to n points; new points are (0,0,0) with default channel values
  /// (black, intensity 0, normal (0,0,0)).
  void resize(std::size_t n);

  /// The enabled channels.
  PointChannels channels() const noexcept { return channels_; }
  bool has_colors() const noexcept { return has_all(channels_, PointChannels::Color); }
  bool has_intensity() const noexcept { return has_all(channels_, PointChannels::Intensity); }
  bool has_normals() const noexcept { return has_all(channels_, PointChannels::Normal); }
  /// Enables the channels in `c` (existing points get default values) and
  /// disables the others.
  void set_channels(PointChannels c);
  /// Enables the channels in `c` in addition to those already enabled.
  void add_channels(PointChannels c) { set_channels(channels_ | c); }

  /// Appends a point; enabled channels get default values. Returns its index.
  std::size_t push_back(const Eigen::Vector3f& p);
  /// Appends a point with a color. Precondition: has_colors().
  std::size_t push_back(const Eigen::Vector3f& p, Rgb8 color);
  /// Appends the point `i` of `other` with the channels both clouds carry
  /// (defaults for those only this cloud carries). Precondition: i < other.size().
  std::size_t push_back_from(const PointCloud& other, std::size_t i);

  /// Read access to the coordinates, meters.
  const std::vector<Eigen::Vector3f>& points() const noexcept { return points_; }
  /// Write access to the coordinates (the count cannot change through it).
  std::span<Eigen::Vector3f> points_mut() noexcept { return points_; }
  /// Point i. Unchecked, as std::vector::operator[].
  const Eigen::Vector3f& operator[](std::size_t i) const noexcept { return points_[i]; }
  Eigen::Vector3f& operator[](std::size_t i) noexcept { return points_[i]; }

  /// Colors (empty span unless has_colors()).
  std::span<const Rgb8> colors() const noexcept { return colors_; }
  std::span<Rgb8> colors_mut() noexcept { return colors_; }
  /// Intensities (empty span unless has_intensity()).
  std::span<const float> intensities() const noexcept { return intensity_; }
  std::span<float> intensities_mut() noexcept { return intensity_; }
  /// Normals (empty span unless has_normals()).
  std::span<const Eigen::Vector3f> normals() const noexcept { return normals_; }
  std::span<Eigen::Vector3f> normals_mut() noexcept { return normals_; }

  /// Keeps the points whose keep[i] is true, in order (all channels alike).
  /// Precondition: keep.size() == size().
  void filter(const std::vector<bool>& keep);
  /// A new cloud with the points listed in `indices` (in that order; repeats
  /// allowed) and the same channels. Precondition: every index < size().
  PointCloud select(std::span<const std::size_t> indices) const;
  /// Appends every point of `other`; channels are those of this cloud
  /// (values taken from `other` where it has them, defaults otherwise).
  void append(const PointCloud& other);

  /// The bounding box of the finite points (empty() if there is none).
  BoundingBox3 bounding_box() const noexcept;
  /// Number of points whose three coordinates are finite.
  std::size_t count_finite() const noexcept;

  /// Exact equality of coordinates, channel set and channel values (NaN
  /// coordinates compare equal to NaN, so loaded clouds can be compared).
  friend bool operator==(const PointCloud& a, const PointCloud& b) noexcept;

 private:
  std::vector<Eigen::Vector3f> points_;
  std::vector<Rgb8> colors_;
  std::vector<float> intensity_;
  std::vector<Eigen::Vector3f> normals_;
  PointChannels channels_ = PointChannels::None;
};

}  // namespace rove
