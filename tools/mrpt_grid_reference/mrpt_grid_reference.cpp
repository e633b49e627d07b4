// Writes MRPT 2.5.8 reference outputs for rove's occupancy grid tests.
//
// Usage: rove_mrpt_grid_reference <datasets/mrpt dir> <output dir>
//
// Outputs (in <output dir>):
//   grid_<name>.bin.gz   grid built by COccupancyGridMap2D (format below)
//   grid_likelihood_reference.txt   likelihoods of chosen scans/poses
//   grid_gridmap_digest.txt         geometry + FNV-1a hash of .gridmap files
//   grid_entropy_reference.txt      computeEntropy of the grids above
//
// grid_<name>.bin.gz (little-endian): u32 magic 0x44495247 ("GRID"),
// f32 x_min, x_max, y_min, y_max, resolution, u32 size_x, size_y,
// size_x*size_y i8 cells (row by row), u32 number of insertions, then per
// insertion f64 x, y, z, yaw, pitch, roll of the robot pose used.
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/maps/CSimpleMap.h>
#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CRawlog.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/poses/CPose3DPDF.h>
#include <mrpt/serialization/CArchive.h>

#include <cinttypes>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iostream>
#include <string>
#include <utility>
#include <vector>

using mrpt::maps::COccupancyGridMap2D;
using mrpt::obs::CObservation2DRangeScan;
using mrpt::poses::CPose2D;
using mrpt::poses::CPose3D;

namespace {

struct Insertion {
  CPose3D pose;
  CObservation2DRangeScan::Ptr scan;
};

template <typename T>
void put(mrpt::io::CFileGZOutputStream& f, const T& v) {
  f.Write(&v, sizeof(T));
}

void write_grid(const std::string& path, const COccupancyGridMap2D& g,
                const std::vector<Insertion>& ins) {
  mrpt::io::CFileGZOutputStream f(path);
  put(f, std::uint32_t{0x44495247});
  put(f, g.getXMin());
  put(f, g.getXMax());
  put(f, g.getYMin());
  put(f, g.getYMax());
  put(f, g.getResolution());
  put(f, std::uint32_t{g.getSizeX()});
  put(f, std::uint32_t{g.getSizeY()});
  const auto& m = g.getRawMap();
  f.Write(m.data(), m.size());
  put(f, static_cast<std::uint32_t>(ins.size()));
  for (const auto& i : ins) {
    for (double v : {i.pose.x(), i.pose.y(), i.pose.z(), i.pose.yaw(), i.pose.pitch(),
                     i.pose.roll()}) {
      put(f, v);
    }
  }
}

// A copy without the cached points map (MRPT caches the first points map
// built from a scan, whatever the options of later calls).
CObservation2DRangeScan fresh(const CObservation2DRangeScan& s) {
  CObservation2DRangeScan o;
  o.aperture = s.aperture;
  o.rightToLeft = s.rightToLeft;
  o.maxRange = s.maxRange;
  o.sensorPose = s.sensorPose;
  o.stdError = s.stdError;
  o.beamAperture = s.beamAperture;
  o.sensorLabel = s.sensorLabel;
  o.resizeScan(s.getScanSize());
  for (size_t i = 0; i < s.getScanSize(); ++i) {
    o.setScanRange(i, s.getScanRange(i));
    o.setScanRangeValidity(i, s.getScanRangeValidity(i));
  }
  return o;
}

std::vector<Insertion> from_simplemap(const std::string& path) {
  mrpt::maps::CSimpleMap sm;
  mrpt::io::CFileGZInputStream f(path);
  mrpt::serialization::archiveFrom(f) >> sm;
  std::vector<Insertion> out;
  for (const auto& kf : sm) {
    const CPose3D pose = kf.pose->getMeanVal();
    for (const auto& o : *kf.sf) {
      if (auto s = std::dynamic_pointer_cast<CObservation2DRangeScan>(o)) out.push_back({pose, s});
    }
  }
  return out;
}

std::vector<Insertion> from_rawlog_odometry(const std::string& path) {
  mrpt::io::CFileGZInputStream f(path);
  auto ar = mrpt::serialization::archiveFrom(f);
  std::vector<Insertion> out;
  CPose2D pose;
  mrpt::obs::CActionCollection::Ptr acts;
  mrpt::obs::CSensoryFrame::Ptr sf;
  mrpt::obs::CObservation::Ptr obs;
  size_t idx = 0;
  while (mrpt::obs::CRawlog::getActionObservationPairOrObservation(ar, acts, sf, obs, idx)) {
    if (!acts || !sf) continue;
    if (auto mv = acts->getBestMovementEstimation()) {
      pose = pose + mv->poseChange->getMeanVal();
    }
    for (const auto& o : *sf) {
      if (auto s = std::dynamic_pointer_cast<CObservation2DRangeScan>(o)) {
        out.push_back({CPose3D(pose), s});
      }
    }
  }
  return out;
}

COccupancyGridMap2D build(const std::vector<Insertion>& ins, float res, bool widening,
                          unsigned decimation, bool invalid_free) {
  COccupancyGridMap2D g(-10, 10, -10, 10, res);
  g.insertionOptions.wideningBeamsWithDistance = widening;
  g.insertionOptions.decimation = static_cast<uint16_t>(decimation);
  g.insertionOptions.considerInvalidRangesAsFreeSpace = invalid_free;
  for (const auto& i : ins) g.insertObservation(*i.scan, i.pose);
  return g;
}

std::uint64_t fnv1a(const void* data, size_t n, std::uint64_t h = 1469598103934665603ull) {
  const auto* p = static_cast<const unsigned char*>(data);
  for (size_t i = 0; i < n; ++i) {
    h ^= p[i];
    h *= 1099511628211ull;
  }
  return h;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::cerr << "usage: " << argv[0] << " <datasets/mrpt dir> <output dir>\n";
    return 2;
  }
  const std::string in = argv[1], out = argv[2];

  // 1) Grids.
  const auto malaga = from_simplemap(in + "/malaga-cs-fac-building.simplemap.gz");
  const auto locdemo = from_simplemap(in + "/localization_demo.simplemap.gz");
  const auto telecom =
      from_rawlog_odometry(in + "/2006-01ENE-21-SENA_Telecom_Faculty_one_loop_only.rawlog");
  const auto g_malaga = build(malaga, 0.05f, false, 1, true);
  write_grid(out + "/grid_malaga_005.bin.gz", g_malaga, malaga);
  const auto g_loc = build(locdemo, 0.10f, true, 2, false);
  write_grid(out + "/grid_locdemo_widening_010.bin.gz", g_loc, locdemo);
  auto g_tel = build(telecom, 0.05f, false, 1, true);
  write_grid(out + "/grid_telecom_005.bin.gz", g_tel, telecom);
  std::cout << "malaga " << malaga.size() << " scans, locdemo " << locdemo.size()
            << ", telecom " << telecom.size() << "\n";

  // 2) Likelihoods on the Telecom grid: chosen scans at their odometry pose
  // and two perturbed poses, every method with defaults, and LF-Thrun
  // variants.
  FILE* lf = std::fopen((out + "/grid_likelihood_reference.txt").c_str(), "w");
  std::fprintf(lf,
               "# scan dx dy dphi method lf_decimation lf_alternate lf_square value "
               "(MRPT 2.5.8 COccupancyGridMap2D, grid_telecom_005)\n");
  struct Variant {
    int method;
    unsigned dec;
    bool alt, sq;
  };
  std::vector<Variant> variants;
  for (int m = 0; m <= 6; ++m) variants.push_back({m, 5, false, false});
  variants.push_back({4, 1, false, false});
  variants.push_back({4, 1, true, false});
  variants.push_back({4, 1, false, true});
  variants.push_back({5, 1, true, false});
  const double offsets[][3] = {{0, 0, 0}, {0.05, -0.03, 0.02}, {-0.2, 0.1, -0.05}};
  // Scans whose points (MRPT's default points map) all fall inside the grid
  // at every evaluated pose: MRPT reads outside its cell array otherwise.
  std::vector<size_t> chosen;
  for (size_t si = 5; si < telecom.size() && chosen.size() < 4; si += 9) {
    const auto s = fresh(*telecom[si].scan);
    const auto* pts = s.buildAuxPointsMap<mrpt::maps::CPointsMap>();
    bool inside = true;
    for (const auto& off : offsets) {
      const CPose2D p(telecom[si].pose + CPose3D(off[0], off[1], 0, off[2], 0, 0));
      for (size_t k = 0; k < pts->size() && inside; ++k) {
        float lx, ly;
        pts->getPoint(k, lx, ly);
        double gx, gy;
        p.composePoint(lx, ly, gx, gy);
        const int cx = g_tel.x2idx(gx), cy = g_tel.y2idx(gy);
        inside = cx >= 2 && cy >= 2 && cx < static_cast<int>(g_tel.getSizeX()) - 2 &&
                 cy < static_cast<int>(g_tel.getSizeY()) - 2;
      }
    }
    if (inside) chosen.push_back(si);
  }
  for (size_t si : chosen) {
    for (const auto& off : offsets) {
      const CPose3D p = telecom[si].pose + CPose3D(off[0], off[1], 0, off[2], 0, 0);
      for (const auto& v : variants) {
        COccupancyGridMap2D g(g_tel);
        g.likelihoodOptions.likelihoodMethod =
            static_cast<COccupancyGridMap2D::TLikelihoodMethod>(v.method);
        g.likelihoodOptions.LF_decimation = v.dec;
        g.likelihoodOptions.LF_alternateAverageMethod = v.alt;
        g.likelihoodOptions.LF_useSquareDist = v.sq;
        const auto s = fresh(*telecom[si].scan);
        const double val = g.computeObservationLikelihood(s, p);
        std::fprintf(lf, "%zu %.17g %.17g %.17g %d %u %d %d %.17g\n", si, off[0], off[1], off[2],
                     v.method, v.dec, v.alt ? 1 : 0, v.sq ? 1 : 0, val);
      }
    }
  }
  std::fclose(lf);

  std::vector<std::pair<std::string, COccupancyGridMap2D>> grids_for_entropy = {
      {"grid_malaga_005", g_malaga}, {"grid_locdemo_widening_010", g_loc}, {"grid_telecom_005", g_tel}};

  // 3) .gridmap digests.
  std::ofstream dg(out + "/grid_gridmap_digest.txt");
  dg << "# file size_x size_y x_min x_max y_min y_max resolution fnv1a64(cells) "
        "n_occupied(<0) n_free(>0)\n";
  for (const std::string& name :
       {std::string("2006-MalagaCampus.gridmap.gz"),
        std::string("uwb_ro-localization_demo_map.gridmap.gz")}) {
    const std::string path = name.rfind("uwb", 0) == 0
                                 ? "/usr/share/mrpt/datasets/" + name
                                 : in + "/" + name;
    COccupancyGridMap2D g;
    mrpt::io::CFileGZInputStream f(path);
    mrpt::serialization::archiveFrom(f) >> g;
    const auto& m = g.getRawMap();
    size_t occ = 0, fr = 0;
    for (auto c : m) {
      occ += c < 0;
      fr += c > 0;
    }
    char buf[512];
    std::snprintf(buf, sizeof buf, "%s %u %u %.9g %.9g %.9g %.9g %.9g %016" PRIx64 " %zu %zu\n",
                  name.c_str(), g.getSizeX(), g.getSizeY(), g.getXMin(), g.getXMax(), g.getYMin(),
                  g.getYMax(), g.getResolution(), fnv1a(m.data(), m.size()), occ, fr);
    dg << buf;
    grids_for_entropy.emplace_back(name, g);
  }

  // 4) computeEntropy of every grid above.
  FILE* ef = std::fopen((out + "/grid_entropy_reference.txt").c_str(), "w");
  std::fprintf(ef, "# grid H I mean_H mean_I effectiveMappedArea effectiveMappedCells "
                   "(MRPT 2.5.8 COccupancyGridMap2D::computeEntropy)\n");
  for (const auto& [name, g] : grids_for_entropy) {
    COccupancyGridMap2D::TEntropyInfo info;
    g.computeEntropy(info);
    std::fprintf(ef, "%s %.17g %.17g %.17g %.17g %.17g %lu\n", name.c_str(), info.H, info.I,
                 info.mean_H, info.mean_I, info.effectiveMappedArea, info.effectiveMappedCells);
  }
  std::fclose(ef);
  return 0;
}
