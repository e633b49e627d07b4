#pragma once
/// \file
/// How well a set of matched surface points constrains a rigid motion.
///
/// For points pᵢ with unit normals nᵢ, the point-to-plane information of a
/// small motion (translation δt, rotation δω about the centroid c) is
/// A = Σ jᵢjᵢᵀ, jᵢ = (nᵢ, ((pᵢ − c) × nᵢ)/L), L the RMS distance of the
/// points from c (so both blocks are unitless and the measure does not
/// depend on the unit of length or on the frame origin). The conditioning
/// λmin(A)/λmax(A) is 0 when a motion leaves every point on its surface (a
/// plane slides and spins in itself; a corridor slides along its axis) and
/// near 1 for well-spread surfaces (Gelfand et al., "Geometrically stable
/// sampling for the ICP algorithm", 3DIM 2003, Sec. 3).

#include <span>
#include <string>
#include <string_view>

#include <Eigen/Core>

namespace rove {

/// Conditioning of the 6-DoF point-to-plane information (see the file
/// comment); 0 for fewer than 6 points or all-zero normals.
/// Precondition: points.size() == normals.size().
double point_to_plane_conditioning(std::span<const Eigen::Vector3d> points,
                                   std::span<const Eigen::Vector3d> normals);

/// The message of a Degenerate termination: "the matched geometry leaves a
/// direction unconstrained (conditioning c < threshold, e.g. <example>)".
std::string degenerate_geometry_message(double conditioning, double threshold,
                                        std::string_view example);

}  // namespace rove
