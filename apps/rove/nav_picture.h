#pragma once
/// \file
/// Pictures of navigation on a map (`rove nav plan`, `rove nav run`): the
/// grid's obstacles in black, the band closer than the robot radius in a
/// light tint, free space in white, with paths and points drawn on top;
/// written as a palette PNG.

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "canvas.h"
#include "rove/nav/navigation_grid.h"

namespace rove::cli {

/// Palette indices of a navigation picture.
enum NavColor : std::uint8_t {
  kNavFree = 0,
  kNavObstacle,
  kNavInflated,
  kNavPlanned,
  kNavDriven,
  kNavStart,
  kNavGoal,
  kNavRobot,
  kNavScan,
  kNavLocal,
  kNavCollision,
  kNavSeparator,
};

/// A picture of a window of the map, `pixels_per_cell` pixels per cell.
class NavPicture {
 public:
  /// The window [x0, x1] × [y0, y1] (meters) of `grid`; cells closer than
  /// `radius` to an obstacle are tinted. At most `max_side` pixels a side:
  /// the scale shrinks to fit.
  NavPicture(const NavigationGrid& grid, double radius, double x0, double y0, double x1, double y1,
             int max_side = 4096, double pixels_per_cell = 1.0);
  /// The whole grid.
  NavPicture(const NavigationGrid& grid, double radius, int max_side = 4096);

  /// A polyline through world points, `width` pixels wide (1 or more).
  void polyline(const std::vector<Eigen::Vector2d>& points, std::uint8_t color, int width = 1);
  /// A filled disc of `r` pixels at a world point.
  void dot(const Eigen::Vector2d& p, int r, std::uint8_t color);
  /// A circle of `radius` meters (outline) at a world point with a heading tick.
  void robot(const Eigen::Vector2d& p, double heading, double radius, std::uint8_t color);
  /// The raster.
  const Canvas& canvas() const { return canvas_; }
  /// Writes the picture as a palette PNG (atomically).
  void write(const std::string& path) const;
  /// Writes several pictures side by side (a strip), each separated by a
  /// gray bar; they need not have the same size.
  static void write_strip(const std::vector<NavPicture>& frames, const std::string& path);

 private:
  int px(double x) const;
  int py(double y) const;
  double x0_, y0_, scale_;  // pixels per meter
  Canvas canvas_;
};

}  // namespace rove::cli
