// NDT with NdtCompat::Pcl: PCL 1.13's NormalDistributionsTransform, for
// parity with it (test NdtPclCompat.*): Newton steps on Euler
// parameters (x, y, z, roll, pitch, yaw) with R = Rx·Ry·Rz (2D: x, y, phi)
// and PCL's convergence rule (ndt_solver.h, run_ndt). Built with
// -ffp-contract=off (cmake/RoveModule.cmake). rove's default, on the right
// tangent of the group, is in ndt.cpp.

// GCC 12 at -O3 reports -Wmaybe-uninitialized inside Eigen's JacobiSVD once
// it is inlined here (see ndt.cpp).
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
#include "ndt_pcl.h"

namespace rove::detail {

NdtSolution<NdtSe3> ndt_pcl_3d(const NdtGrid3D& grid, std::span<const Eigen::Vector3f> source,
                               const SE3d& initial, const NdtOptions& o) {
  return as_group_solution<NdtSe3>(
      ndt_solve<PclEuler3>(grid, source, PclEuler3::from_group(initial), o, true));
}

NdtSolution<NdtSe2> ndt_pcl_2d(const NdtGrid2D& grid, std::span<const Eigen::Vector2f> source,
                               const SE2d& initial, const NdtOptions& o) {
  return as_group_solution<NdtSe2>(
      ndt_solve<PclPlanar>(grid, source, PclPlanar::from_group(initial), o, true));
}

}  // namespace rove::detail
