// Writes MRPT 2.5.8's multi-metric map built from a config section and a
// simplemap, in a text form rove's tests read:
//   map <index> <class>
//   points <n>                                  (point maps)
//   grid <size_x> <size_y> <x_min> <x_max> <y_min> <y_max> <resolution>
//   <size_y rows of size_x characters: '#' occupied (p_free < 0.4),
//    '.' free (p_free > 0.6), '?' otherwise>   (occupancy grids)
//
// Usage: rove_mrpt_multimap_reference CONFIG SECTION SIMPLEMAP OUT.txt
#include <mrpt/config/CConfigFile.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/maps/CMultiMetricMap.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/maps/CPointsMap.h>
#include <mrpt/maps/CSimpleMap.h>
#include <mrpt/serialization/CArchive.h>

#include <cstdio>
#include <fstream>
#include <iostream>
#include <string>

int main(int argc, char** argv) {
  if (argc != 5) {
    std::cerr << "usage: " << argv[0] << " CONFIG SECTION SIMPLEMAP OUT.txt\n";
    return 2;
  }
  mrpt::config::CConfigFile ini(argv[1]);
  mrpt::maps::TSetOfMetricMapInitializers inits;
  inits.loadFromConfigFile(ini, argv[2]);
  mrpt::maps::CMultiMetricMap mm;
  mm.setListOfMaps(inits);

  mrpt::maps::CSimpleMap sm;
  mrpt::io::CFileGZInputStream f(argv[3]);
  mrpt::serialization::archiveFrom(f) >> sm;
  mm.loadFromProbabilisticPosesAndObservations(sm);

  std::ofstream out(argv[4]);
  const auto base = [](const std::string& path) { return path.substr(path.find_last_of('/') + 1); };
  out << "# MRPT 2.5.8 CMultiMetricMap from [" << argv[2] << "] of " << base(argv[1]) << " and "
      << base(argv[3]) << "\n";
  for (std::size_t i = 0; i < mm.maps.size(); ++i) {
    const auto& m = mm.maps[i];
    out << "map " << i << " " << m->GetRuntimeClass()->className << "\n";
    if (const auto* p = dynamic_cast<const mrpt::maps::CPointsMap*>(m.get())) {
      out << "points " << p->size() << "\n";
    }
    if (const auto* g = dynamic_cast<const mrpt::maps::COccupancyGridMap2D*>(m.get())) {
      char buf[256];
      std::snprintf(buf, sizeof buf, "grid %u %u %.6f %.6f %.6f %.6f %.6f\n", g->getSizeX(),
                    g->getSizeY(), g->getXMin(), g->getXMax(), g->getYMin(), g->getYMax(),
                    g->getResolution());
      out << buf;
      for (unsigned cy = 0; cy < g->getSizeY(); ++cy) {
        std::string row(g->getSizeX(), '?');
        for (unsigned cx = 0; cx < g->getSizeX(); ++cx) {
          const float p = g->getCell(cx, cy);
          row[cx] = p < 0.4f ? '#' : (p > 0.6f ? '.' : '?');
        }
        out << row << "\n";
      }
    }
  }
  return 0;
}
