// Reference generator for mrpt_sena_reference.txt (not built with rove; it
// links MRPT 2.5.8). Build with the MRPT headers and libraries on the include
// and library paths, e.g. on Debian:
//   g++ -std=c++17 $(for d in /usr/include/mrpt/*/include; do echo -I$d; done) \
//     -I/usr/include/eigen3 mrpt_reference_generator.cc -lmrpt-obs -lmrpt-poses \
//     -lmrpt-io -lmrpt-serialization -lmrpt-core -lmrpt-math -lmrpt-system -lmrpt-rtti
// Run: ./a.out RAWLOG > out.txt, then keep the first and last 5 lines of each kind.
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/serialization/CArchive.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/obs/CObservationBearingRange.h>
#include <mrpt/obs/CObservationBeaconRanges.h>
#include <mrpt/poses/CPosePDFGaussian.h>
#include <cstdio>
using namespace mrpt;
int main(int, char** argv) {
  io::CFileGZInputStream f(argv[1]);
  auto ar = serialization::archiveFrom(f);
  int k = 0;
  for (;;) {
    serialization::CSerializable::Ptr o;
    try { ar >> o; } catch (std::exception&) { break; }
    if (auto ac = std::dynamic_pointer_cast<obs::CActionCollection>(o)) {
      auto m = ac->getBestMovementEstimation();
      auto g = std::dynamic_pointer_cast<poses::CPosePDFGaussian>(m->poseChange.get_ptr());
      printf("A %d %llu %.17g %.17g %.17g", k, (unsigned long long)m->timestamp.time_since_epoch().count(),
        m->rawOdometryIncrementReading.x(), m->rawOdometryIncrementReading.y(), m->rawOdometryIncrementReading.phi());
      if (g) for (int i=0;i<3;i++) for(int j=0;j<3;j++) printf(" %.17g", g->cov(i,j));
      printf("\n");
    } else if (auto sf = std::dynamic_pointer_cast<obs::CSensoryFrame>(o)) {
      for (auto& ob : *sf) if (auto s = std::dynamic_pointer_cast<obs::CObservation2DRangeScan>(ob)) {
        printf("S %d %llu %zu %.9g %d %.9g %.9g %.9g", k, (unsigned long long)s->timestamp.time_since_epoch().count(), s->getScanSize(), s->aperture, (int)s->rightToLeft, s->maxRange, s->stdError, s->beamAperture);
        printf(" %.17g %.17g %.17g %.17g %.17g %.17g", s->sensorPose.x(), s->sensorPose.y(), s->sensorPose.z(), s->sensorPose.yaw(), s->sensorPose.pitch(), s->sensorPose.roll());
        for (size_t i=0;i<s->getScanSize();i++) printf(" %.9g", s->getScanRange(i));
        for (size_t i=0;i<s->getScanSize();i++) printf(" %d", (int)s->getScanRangeValidity(i));
        printf("\n");
      }
      for (auto& ob : *sf) if (auto b = std::dynamic_pointer_cast<obs::CObservationBearingRange>(ob)) {
        printf("B %d %llu L=%s %zu %.9g %.9g %.9g %.9g %.17g %.17g %.17g", k, (unsigned long long)b->timestamp.time_since_epoch().count(), b->sensorLabel.c_str(), b->sensedData.size(), b->minSensorDistance, b->maxSensorDistance, b->fieldOfView_yaw, b->fieldOfView_pitch, b->sensorLocationOnRobot.x(), b->sensorLocationOnRobot.y(), b->sensorLocationOnRobot.z());
        for (auto& m : b->sensedData) printf(" %d %.9g %.9g %.9g", m.landmarkID, m.range, m.yaw, m.pitch);
        printf("\n");
      }
      for (auto& ob : *sf) if (auto b = std::dynamic_pointer_cast<obs::CObservationBeaconRanges>(ob)) {
        printf("R %d %llu L=%s %zu %.9g %.9g %.9g", k, (unsigned long long)b->timestamp.time_since_epoch().count(), b->sensorLabel.c_str(), b->sensedData.size(), b->minSensorDistance, b->maxSensorDistance, b->stdError);
        for (auto& m : b->sensedData) printf(" %d %.9g %.17g %.17g %.17g", (int)m.beaconID, m.sensedDistance, m.sensorLocationOnRobot.x(), m.sensorLocationOnRobot.y(), m.sensorLocationOnRobot.z());
        printf("\n");
      }
    }
    ++k;
  }
}
