#include "rove/maps/point_cloud.h"

#include <cmath>
#include <cstring>

#include "rove/core/check.h"

namespace rove {

void PointCloud::clear() noexcept {
  points_.clear();
  colors_.clear();
  intensity_.clear();
  normals_.clear();
}

void PointCloud::reserve(std::size_t n) {
  points_.reserve(n);
  if (has_colors()) colors_.reserve(n);
  if (has_intensity()) intensity_.reserve(n);
  if (has_normals()) normals_.reserve(n);
}

void PointCloud::resize(std::size_t n) {
  points_.resize(n, Eigen::Vector3f::Zero());
  if (has_colors()) colors_.resize(n);
  if (has_intensity()) intensity_.resize(n, 0.0f);
  if (has_normals()) normals_.resize(n, Eigen::Vector3f::Zero());
}

void PointCloud::set_channels(PointChannels c) {
  channels_ = c;
  const std::size_t n = points_.size();
  if (has_colors()) colors_.resize(n); else colors_ = {};
  if (has_intensity()) intensity_.resize(n, 0.0f); else intensity_ = {};
  if (has_normals()) normals_.resize(n, Eigen::Vector3f::Zero()); else normals_ = {};
}

std::size_t PointCloud::push_back(const Eigen::Vector3f& p) {
  points_.push_back(p);
  if (has_colors()) colors_.emplace_back();
  if (has_intensity()) intensity_.push_back(0.0f);
  if (has_normals()) normals_.push_back(Eigen::Vector3f::Zero());
  return points_.size() - 1;
}

std::size_t PointCloud::push_back(const Eigen::Vector3f& p, Rgb8 color) {
  ROVE_CHECK_MSG(has_colors(), "push_back with a color on a cloud without a color channel");
  const std::size_t i = push_back(p);
  colors_[i] = color;
  return i;
}

std::size_t PointCloud::push_back_from(const PointCloud& other, std::size_t i) {
  ROVE_CHECK_LT(i, other.size());
  const std::size_t j = push_back(other.points_[i]);
  if (has_colors() && other.has_colors()) colors_[j] = other.colors_[i];
  if (has_intensity() && other.has_intensity()) intensity_[j] = other.intensity_[i];
  if (has_normals() && other.has_normals()) normals_[j] = other.normals_[i];
  return j;
}

namespace {
template <typename T>
void keep_if(std::vector<T>& v, const std::vector<bool>& keep) {
  if (v.empty()) return;
  std::size_t w = 0;
  for (std::size_t i = 0; i < v.size(); ++i)
    if (keep[i]) v[w++] = v[i];
  v.resize(w);
}
template <typename T>
std::vector<T> pick(const std::vector<T>& v, std::span<const std::size_t> idx) {
  std::vector<T> out;
  if (v.empty()) return out;
  out.reserve(idx.size());
  for (std::size_t i : idx) out.push_back(v[i]);
  return out;
}
}  // namespace

void PointCloud::filter(const std::vector<bool>& keep) {
  ROVE_CHECK_EQ(keep.size(), size());
  keep_if(points_, keep);
  keep_if(colors_, keep);
  keep_if(intensity_, keep);
  keep_if(normals_, keep);
}

PointCloud PointCloud::select(std::span<const std::size_t> indices) const {
  for (std::size_t i : indices) ROVE_CHECK_LT(i, size());
  PointCloud out;
  out.channels_ = channels_;
  out.points_ = pick(points_, indices);
  out.colors_ = pick(colors_, indices);
  out.intensity_ = pick(intensity_, indices);
  out.normals_ = pick(normals_, indices);
  return out;
}

void PointCloud::append(const PointCloud& other) {
  reserve(size() + other.size());
  for (std::size_t i = 0; i < other.size(); ++i) push_back_from(other, i);
}

BoundingBox3 PointCloud::bounding_box() const noexcept {
  BoundingBox3 box;
  bool any = false;
  for (const auto& p : points_) {
    if (!p.allFinite()) continue;
    if (!any) {
      box.min = box.max = p;
      any = true;
    } else {
      box.min = box.min.cwiseMin(p);
      box.max = box.max.cwiseMax(p);
    }
  }
  return box;
}

std::size_t PointCloud::count_finite() const noexcept {
  std::size_t n = 0;
  for (const auto& p : points_) n += p.allFinite() ? 1 : 0;
  return n;
}

namespace {
bool same_float(float a, float b) noexcept {
  return a == b || (std::isnan(a) && std::isnan(b));
}
bool same_vectors(const std::vector<Eigen::Vector3f>& a, const std::vector<Eigen::Vector3f>& b) noexcept {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i)
    for (int k = 0; k < 3; ++k)
      if (!same_float(a[i][k], b[i][k])) return false;
  return true;
}
}  // namespace

bool operator==(const PointCloud& a, const PointCloud& b) noexcept {
  if (a.channels_ != b.channels_ || !same_vectors(a.points_, b.points_) ||
      !same_vectors(a.normals_, b.normals_) || a.colors_ != b.colors_ ||
      a.intensity_.size() != b.intensity_.size())
    return false;
  for (std::size_t i = 0; i < a.intensity_.size(); ++i)
    if (!same_float(a.intensity_[i], b.intensity_[i])) return false;
  return true;
}

}  // namespace rove
