#pragma once
// Internal: archive encodings of the pose types rove::obs stores, and the
// conversion of a rejected value into a ParseError while loading
// (rove/serialization/parse_guard.h).

#include <string_view>

#include "rove/poses/pdf_gaussian2.h"
#include "rove/poses/pose2.h"
#include "rove/poses/pose3.h"
#include "rove/serialization/archive.h"
#include "rove/serialization/parse_guard.h"

namespace rove::detail {

/// Pose2 as x, y, phi (3 doubles).
void save_pose2(OutArchive& ar, const Pose2& p);
/// Reads a Pose2; a non-finite value is a ParseError naming `field`.
Pose2 load_pose2(InArchive& ar, std::string_view field);
/// Pose3 as its rotation matrix (9 doubles, column-major) and translation
/// (3 doubles): exact, no Euler-angle round trip.
void save_pose3(OutArchive& ar, const Pose3& p);
/// Reads a Pose3; a non-rotation matrix or a non-finite value is a
/// ParseError naming `field`.
Pose3 load_pose3(InArchive& ar, std::string_view field);
/// Pose2Gaussian as mean (Pose2) and covariance (9 doubles, column-major).
void save_pose2_gaussian(OutArchive& ar, const Pose2Gaussian& g);
/// Reads a Pose2Gaussian; an invalid covariance is a ParseError.
Pose2Gaussian load_pose2_gaussian(InArchive& ar, std::string_view field);

}  // namespace rove::detail

