// Copies an MRPT rawlog object by object, giving every observation with an
// empty sensor label the label LASER (2D range scans) or ODOMETRY (odometry).
// With a third argument N, only the first N top-level objects are copied.
//
//   rove_mrpt_rawlog_relabel IN.rawlog OUT.rawlog [N]
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/serialization/CArchive.h>

#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>

namespace {

void relabel(mrpt::obs::CObservation& o) {
  if (!o.sensorLabel.empty()) return;
  if (dynamic_cast<mrpt::obs::CObservation2DRangeScan*>(&o) != nullptr) o.sensorLabel = "LASER";
  if (dynamic_cast<mrpt::obs::CObservationOdometry*>(&o) != nullptr) o.sensorLabel = "ODOMETRY";
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3 && argc != 4) {
    std::fprintf(stderr, "usage: %s IN.rawlog OUT.rawlog [N]\n", argv[0]);
    return 2;
  }
  try {
    const long limit = argc == 4 ? std::atol(argv[3]) : -1;
    mrpt::io::CFileGZInputStream in(argv[1]);
    mrpt::io::CFileGZOutputStream out(argv[2]);
    auto ar_in = mrpt::serialization::archiveFrom(in);
    auto ar_out = mrpt::serialization::archiveFrom(out);
    long copied = 0;
    while (limit < 0 || copied < limit) {
      mrpt::serialization::CSerializable::Ptr obj;
      try {
        ar_in >> obj;
      } catch (const std::exception&) {
        break;  // end of file
      }
      if (auto sf = std::dynamic_pointer_cast<mrpt::obs::CSensoryFrame>(obj)) {
        for (auto& o : *sf) relabel(*o);
      } else if (auto o = std::dynamic_pointer_cast<mrpt::obs::CObservation>(obj)) {
        relabel(*o);
      }
      ar_out << *obj;
      ++copied;
    }
    std::printf("%ld objects copied\n", copied);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
  return 0;
}
