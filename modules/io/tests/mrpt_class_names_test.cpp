// MRPT 2.x writes class names with their namespace; older files without.
// Both must be read (regression: rawlogs written by MRPT 2.5.8's
// carmen2rawlog were rejected as "no reader for mrpt::obs::CObservationOdometry").
#include <gtest/gtest.h>

#include "rove/io/mrpt_objects.h"

TEST(MrptClassNames, BareAndNamespacedSpellingsAreSupported) {
  for (const char* name : {"CObservation2DRangeScan", "mrpt::obs::CObservation2DRangeScan",
                           "CObservationOdometry", "mrpt::obs::CObservationOdometry",
                           "CSensoryFrame", "mrpt::obs::CSensoryFrame", "CActionCollection",
                           "mrpt::obs::CActionCollection", "CPose3D", "mrpt::poses::CPose3D",
                           "CMatrixD", "mrpt::math::CMatrixD"}) {
    EXPECT_TRUE(rove::is_supported_mrpt_class(name)) << name;
  }
  EXPECT_FALSE(rove::is_supported_mrpt_class("mrpt::obs::CPose3D"));
  EXPECT_FALSE(rove::is_supported_mrpt_class("mrpt::obs::CObservationStereoImages"));
}
