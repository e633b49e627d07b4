// Runs MRPT 2.5.8's PlannerSimple2D on an MRPT .gridmap[.gz] and prints the
// path (origin, the planner's points, target) and its length in meters.
//
//   rove_mrpt_nav_reference MAP.gridmap.gz RADIUS X0 Y0 X1 Y1 [--points]
//
// The length is the sum of the straight segments from the origin through
// every returned point (the last one is the target), as rove's planners
// report it.
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/nav/planners/PlannerSimple2D.h>
#include <mrpt/serialization/CArchive.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <deque>

int main(int argc, char** argv) {
  if (argc < 7) {
    std::fprintf(stderr, "usage: %s MAP.gridmap[.gz] RADIUS X0 Y0 X1 Y1 [--points]\n", argv[0]);
    return 2;
  }
  mrpt::io::CFileGZInputStream f(argv[1]);
  if (!f.fileOpenCorrectly()) {
    std::fprintf(stderr, "cannot open %s\n", argv[1]);
    return 1;
  }
  mrpt::maps::COccupancyGridMap2D grid;
  mrpt::serialization::archiveFrom(f) >> grid;
  mrpt::nav::PlannerSimple2D planner;
  planner.robotRadius = static_cast<float>(std::atof(argv[2]));
  const mrpt::poses::CPose2D origin(std::atof(argv[3]), std::atof(argv[4]), 0);
  const mrpt::poses::CPose2D target(std::atof(argv[5]), std::atof(argv[6]), 0);
  std::deque<mrpt::math::TPoint2D> path;
  bool not_found = true;
  const auto t0 = std::chrono::steady_clock::now();
  planner.computePath(grid, origin, target, path, not_found);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (not_found) {
    std::printf("not found (%.3f s)\n", seconds);
    return 3;
  }
  double length = 0, px = origin.x(), py = origin.y();
  for (const auto& p : path) {
    length += std::hypot(p.x - px, p.y - py);
    px = p.x;
    py = p.y;
  }
  std::printf("points %zu length %.6f m time %.3f s\n", path.size(), length, seconds);
  if (argc > 7 && std::strcmp(argv[7], "--points") == 0) {
    for (const auto& p : path) std::printf("%.4f %.4f\n", p.x, p.y);
  }
  return 0;
}
