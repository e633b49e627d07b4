// Reference generator for mrpt_*_simplemap_reference.txt (links MRPT 2.5.8;
// built like mrpt_reference_generator.cc, adding -lmrpt-maps).
// Run: ./a.out FILE.simplemap.gz, then keep the N line, the first 3 and the last K lines.
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/serialization/CArchive.h>
#include <mrpt/maps/CSimpleMap.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/poses/CPose3DPDFGaussian.h>
#include <cstdio>
int main(int, char** argv) {
  mrpt::io::CFileGZInputStream f(argv[1]);
  auto ar = mrpt::serialization::archiveFrom(f);
  mrpt::maps::CSimpleMap sm;
  ar >> sm;
  printf("N %zu\n", sm.size());
  for (size_t k = 0; k < sm.size(); ++k) {
    mrpt::poses::CPose3DPDF::Ptr p; mrpt::obs::CSensoryFrame::Ptr sf;
    sm.get(k, p, sf);
    auto g = std::dynamic_pointer_cast<mrpt::poses::CPose3DPDFGaussian>(p);
    printf("K %zu %.17g %.17g %.17g %.17g %.17g %.17g", k, g->mean.x(), g->mean.y(), g->mean.z(), g->mean.yaw(), g->mean.pitch(), g->mean.roll());
    for (int i=0;i<6;i++) for(int j=0;j<6;j++) printf(" %.17g", g->cov(i,j));
    size_t ns = 0; float r0 = 0, rl = 0; unsigned long long ts = 0;
    for (auto& o : *sf) if (auto s = std::dynamic_pointer_cast<mrpt::obs::CObservation2DRangeScan>(o)) { if (!ns) { ns = s->getScanSize(); r0 = s->getScanRange(0); rl = s->getScanRange(ns-1); ts = s->timestamp.time_since_epoch().count(); } }
    printf(" %zu %zu %llu %.9g %.9g\n", sf->size(), ns, ts, r0, rl);
  }
}
