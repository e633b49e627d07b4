#pragma once
// The precondition on a 3D solver's initial transform, shared by icp_3d and
// ndt_3d.

#include <Eigen/Geometry>

#include "rove/core/check.h"

namespace rove::detail {

/// Throws InvalidArgument unless `initial` is finite and rigid (its linear
/// part orthonormal to 1e-6).
inline void check_rigid_initial(const Eigen::Isometry3d& initial) {
  ROVE_CHECK_FINITE(initial.matrix());
  ROVE_CHECK_MSG((initial.linear().transpose() * initial.linear() - Eigen::Matrix3d::Identity())
                         .cwiseAbs()
                         .maxCoeff() < 1e-6,
                 "the initial transform is not rigid");
}

}  // namespace rove::detail
