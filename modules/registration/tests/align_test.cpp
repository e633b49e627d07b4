// align_clouds: the method by name, the auto voxel schedule, and the
// options' checks (the entry point of `rove align` and rove.align).

#include "rove/registration/align.h"

#include <gtest/gtest.h>

#include "rove/core/error.h"
#include "rove/registration/icp_3d_multi_resolution.h"
#include "synthetic_3d.h"

namespace rove {
namespace {

TEST(Align, EveryMethodRecoversTheRoomPose) {
  const auto room = test::room_3d(0.05);
  const Eigen::Isometry3d T = test::make_pose(0.15, -0.1, 0.05, 0.02, -0.03, 0.08);
  const auto seen = test::as_seen_from(room, T, 0.002, 11);
  for (const AlignMethod m : {AlignMethod::PointToPoint, AlignMethod::PointToPlane,
                              AlignMethod::Gicp, AlignMethod::Ndt}) {
    AlignOptions o;
    o.method = m;
    if (m == AlignMethod::Ndt) o.voxel_sizes = std::vector<double>{0.1};
    const AlignResult r = align_clouds(room, seen, SE3d(), o);
    ASSERT_TRUE(r.ok()) << to_string(m) << ": " << r.message;
    const auto [dt, dr] = test::pose_error(r.T_target_source.matrix(), T.matrix());
    EXPECT_LT(dt, 0.01) << to_string(m);
    EXPECT_LT(dr, 0.005) << to_string(m);
    EXPECT_EQ(r.voxel_auto, m != AlignMethod::Ndt);
  }
}

TEST(Align, AutoVoxelsAreTheTargetsSuggestionAndAFinerLevel) {
  const auto room = test::room_3d(0.02);
  const AlignResult r = align_clouds(room, room);
  ASSERT_EQ(r.voxel_sizes.size(), 2u);
  EXPECT_GT(r.voxel_sizes[0], 0.0);
  EXPECT_NEAR(r.voxel_sizes[1], r.voxel_sizes[0] * AlignOptions::kFineRatio, 1e-4);
  EXPECT_EQ(r.level_messages.size(), 2u);
  // The same as calling the multi-resolution ICP with that schedule.
  Icp3dMultiResolutionOptions mo;
  mo.voxel_sizes = r.voxel_sizes;
  const auto direct = icp_3d_multi_resolution(room, room, SE3d(), mo);
  EXPECT_EQ(direct.result.T_target_source.matrix(), r.T_target_source.matrix());
  EXPECT_EQ(direct.total_iterations, r.iterations);
}

TEST(Align, EmptyCloudsAreInvalidInputNotAnError) {
  const std::vector<Eigen::Vector3f> none;
  AlignOptions o;
  o.voxel_sizes = std::vector<double>{0.5};
  EXPECT_EQ(align_clouds(none, none, SE3d(), o).termination, RegistrationTermination::InvalidInput);
}

TEST(Align, OptionsAreChecked) {
  const auto room = test::room_3d(0.2);
  AlignOptions o;
  o.method = AlignMethod::Ndt;
  o.voxel_sizes = std::vector<double>{0.5, 0.2};
  EXPECT_THROW(align_clouds(room, room, SE3d(), o), InvalidArgument);
  o = {};
  o.neighbors = 2;
  EXPECT_THROW(align_clouds(room, room, SE3d(), o), InvalidArgument);
  o = {};
  o.max_distance = std::nan("");
  EXPECT_THROW(align_clouds(room, room, SE3d(), o), InvalidArgument);
  o = {};
  o.voxel_sizes = std::vector<double>{-1.0};
  EXPECT_THROW(align_clouds(room, room, SE3d(), o), InvalidArgument);
  EXPECT_THROW(parse_align_method("sift"), InvalidArgument);
  for (const AlignMethod m :
       {AlignMethod::PointToPoint, AlignMethod::PointToPlane, AlignMethod::Gicp, AlignMethod::Ndt})
    EXPECT_EQ(parse_align_method(to_string(m)), m);
}

}  // namespace
}  // namespace rove
