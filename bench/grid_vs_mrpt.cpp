// rove OccupancyGrid vs MRPT 2.5.8 COccupancyGridMap2D on the same scans and
// poses (Telecom Faculty rawlog, 224 scans at odometry poses, 5 cm grid).
#include <benchmark/benchmark.h>

#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CRawlog.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/serialization/CArchive.h>

#include <cstdio>
#include <cstdlib>
#include <memory>
#include <vector>

#include "rove/io/rawlog_reader.h"
#include "rove/maps/grid_insertion.h"
#include "rove/maps/grid_likelihood.h"
#include "rove/maps/occupancy_grid.h"

namespace {

const char* kRawlog = ROVE_DATA_DIR "/2006-01ENE-21-SENA_Telecom_Faculty_one_loop_only.rawlog";

struct Data {
  std::vector<mrpt::obs::CObservation2DRangeScan::Ptr> mscans;
  std::vector<mrpt::poses::CPose3D> mposes;
  std::vector<std::shared_ptr<const rove::RangeScan2D>> rscans;
  std::vector<rove::Pose3> rposes;
};

const Data& data() {
  static const Data d = [] {
    Data d;
    mrpt::io::CFileGZInputStream f(kRawlog);
    if (!f.fileOpenCorrectly()) {
      std::fprintf(stderr, "missing %s\n", kRawlog);
      std::exit(1);
    }
    auto ar = mrpt::serialization::archiveFrom(f);
    mrpt::poses::CPose2D pose;
    mrpt::obs::CActionCollection::Ptr acts;
    mrpt::obs::CSensoryFrame::Ptr sf;
    mrpt::obs::CObservation::Ptr obs;
    size_t idx = 0;
    while (mrpt::obs::CRawlog::getActionObservationPairOrObservation(ar, acts, sf, obs, idx)) {
      if (!acts || !sf) continue;
      if (auto mv = acts->getBestMovementEstimation()) pose = pose + mv->poseChange->getMeanVal();
      for (const auto& o : *sf) {
        if (auto s = std::dynamic_pointer_cast<mrpt::obs::CObservation2DRangeScan>(o)) {
          d.mscans.push_back(s);
          d.mposes.emplace_back(pose);
          d.rposes.emplace_back(pose.x(), pose.y(), 0.0, pose.phi(), 0.0, 0.0);
        }
      }
    }
    const rove::Rawlog log = rove::load_rawlog(kRawlog);
    bool after_action = false;
    for (const auto& e : log.entries) {
      if (std::holds_alternative<std::shared_ptr<const rove::ActionCollection>>(e)) after_action = true;
      if (const auto* s = std::get_if<std::shared_ptr<const rove::SensoryFrame>>(&e); s && after_action) {
        after_action = false;
        for (const auto& o : (*s)->observations) {
          if (auto r = std::dynamic_pointer_cast<const rove::RangeScan2D>(o)) d.rscans.push_back(r);
        }
      }
    }
    if (d.rscans.size() != d.mscans.size()) std::exit(2);
    return d;
  }();
  return d;
}

void BM_Insert_Mrpt(benchmark::State& st) {
  const Data& d = data();
  for (auto _ : st) {
    mrpt::maps::COccupancyGridMap2D g(-10, 10, -10, 10, 0.05f);
    for (size_t i = 0; i < d.mscans.size(); ++i) g.insertObservation(*d.mscans[i], d.mposes[i]);
    benchmark::DoNotOptimize(g.getRawMap().data());
  }
  st.SetItemsProcessed(static_cast<int64_t>(st.iterations() * d.mscans.size()));
}
void BM_Insert_Rove(benchmark::State& st) {
  const Data& d = data();
  for (auto _ : st) {
    rove::OccupancyGrid g(-10, 10, -10, 10, 0.05f);
    for (size_t i = 0; i < d.rscans.size(); ++i) rove::insert_scan(g, *d.rscans[i], d.rposes[i]);
    benchmark::DoNotOptimize(g.cells().data());
  }
  st.SetItemsProcessed(static_cast<int64_t>(st.iterations() * d.rscans.size()));
}

// The same insertions into a grid created at its final size (980 × 1200
// cells), so that no growth happens: the ray tracing alone (plus one 1.2 MB
// fill per iteration on both sides).
void BM_InsertPresized_Mrpt(benchmark::State& st) {
  const Data& d = data();
  for (auto _ : st) {
    mrpt::maps::COccupancyGridMap2D g(-29, 20, -39, 21, 0.05f);
    for (size_t i = 0; i < d.mscans.size(); ++i) g.insertObservation(*d.mscans[i], d.mposes[i]);
    benchmark::DoNotOptimize(g.getRawMap().data());
  }
  st.SetItemsProcessed(static_cast<int64_t>(st.iterations() * d.mscans.size()));
}
void BM_InsertPresized_Rove(benchmark::State& st) {
  const Data& d = data();
  for (auto _ : st) {
    rove::OccupancyGrid g(-29, 20, -39, 21, 0.05f);
    for (size_t i = 0; i < d.rscans.size(); ++i) rove::insert_scan(g, *d.rscans[i], d.rposes[i]);
    benchmark::DoNotOptimize(g.cells().data());
  }
  st.SetItemsProcessed(static_cast<int64_t>(st.iterations() * d.rscans.size()));
}

mrpt::maps::COccupancyGridMap2D& mrpt_map() {
  static mrpt::maps::COccupancyGridMap2D g = [] {
    mrpt::maps::COccupancyGridMap2D m(-10, 10, -10, 10, 0.05f);
    const Data& d = data();
    for (size_t i = 0; i < d.mscans.size(); ++i) m.insertObservation(*d.mscans[i], d.mposes[i]);
    m.likelihoodOptions.likelihoodMethod = mrpt::maps::COccupancyGridMap2D::lmLikelihoodField_Thrun;
    m.likelihoodOptions.LF_decimation = 1;
    return m;
  }();
  return g;
}
const rove::OccupancyGrid& rove_map() {
  static rove::OccupancyGrid g = [] {
    rove::OccupancyGrid m(-10, 10, -10, 10, 0.05f);
    const Data& d = data();
    for (size_t i = 0; i < d.rscans.size(); ++i) rove::insert_scan(m, *d.rscans[i], d.rposes[i]);
    return m;
  }();
  return g;
}

// One likelihood evaluation per scan at its pose (MRPT: cache enabled, the
// scan's points map cached in the observation after the first call).
void BM_LikelihoodThrun_Mrpt(benchmark::State& st) {
  const Data& d = data();
  auto& g = mrpt_map();
  double sum = 0;
  for (auto _ : st) {
    for (size_t i = 0; i < d.mscans.size(); ++i) sum += g.computeObservationLikelihood(*d.mscans[i], d.mposes[i]);
  }
  benchmark::DoNotOptimize(sum);
  st.SetItemsProcessed(static_cast<int64_t>(st.iterations() * d.mscans.size()));
}
void BM_LikelihoodThrun_Rove(benchmark::State& st) {
  const Data& d = data();
  rove::GridLikelihoodOptions o;
  o.lf_decimation = 1;
  rove::GridLikelihoodModel<std::int8_t> model(rove_map(), o);
  std::vector<rove::PreparedGridScan> prepared;
  for (const auto& s : d.rscans) prepared.push_back(model.prepare(*s));
  double sum = 0;
  for (auto _ : st) {
    for (size_t i = 0; i < prepared.size(); ++i) sum += model.log_likelihood(prepared[i], rove::Pose2(d.rposes[i]));
  }
  benchmark::DoNotOptimize(sum);
  st.SetItemsProcessed(static_cast<int64_t>(st.iterations() * d.rscans.size()));
}
// Batch: 1000 particle poses around each of 20 scans' poses (as MCL).
std::vector<rove::Pose2> particles(const rove::Pose3& c) {
  std::vector<rove::Pose2> p;
  unsigned s = 12345;
  for (int k = 0; k < 1000; ++k) {
    s = s * 1103515245u + 12345u;
    const double a = ((s >> 8) % 1000) / 1000.0 - 0.5, b = ((s >> 18) % 1000) / 1000.0 - 0.5;
    p.emplace_back(c.x() + 0.4 * a, c.y() + 0.4 * b, c.yaw() + 0.2 * (a * b));
  }
  return p;
}
void BM_LikelihoodBatch_Mrpt(benchmark::State& st) {
  const Data& d = data();
  auto& g = mrpt_map();
  std::vector<std::vector<mrpt::poses::CPose3D>> ps;
  for (size_t i = 0; i < 20; ++i) {
    std::vector<mrpt::poses::CPose3D> v;
    for (const auto& p : particles(d.rposes[i * 10])) v.emplace_back(p.x(), p.y(), 0, p.phi(), 0, 0);
    ps.push_back(v);
  }
  double sum = 0;
  for (auto _ : st) {
    for (size_t i = 0; i < 20; ++i)
      for (const auto& p : ps[i]) sum += g.computeObservationLikelihood(*d.mscans[i * 10], p);
  }
  benchmark::DoNotOptimize(sum);
  st.SetItemsProcessed(static_cast<int64_t>(st.iterations() * 20000));
}
void BM_LikelihoodBatch_Rove(benchmark::State& st) {
  const Data& d = data();
  rove::GridLikelihoodOptions o;
  o.lf_decimation = 1;
  rove::GridLikelihoodModel<std::int8_t> model(rove_map(), o);
  std::vector<std::vector<rove::Pose2>> ps;
  for (size_t i = 0; i < 20; ++i) ps.push_back(particles(d.rposes[i * 10]));
  std::vector<double> out(1000);
  double sum = 0;
  for (auto _ : st) {
    for (size_t i = 0; i < 20; ++i) {
      const auto prepared = model.prepare(*d.rscans[i * 10]);
      model.log_likelihood(prepared, ps[i], out);
      sum += out[0];
    }
  }
  benchmark::DoNotOptimize(sum);
  st.SetItemsProcessed(static_cast<int64_t>(st.iterations() * 20000));
}

BENCHMARK(BM_Insert_Mrpt)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Insert_Rove)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_InsertPresized_Mrpt)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_InsertPresized_Rove)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_LikelihoodThrun_Mrpt)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_LikelihoodThrun_Rove)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_LikelihoodBatch_Mrpt)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_LikelihoodBatch_Rove)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
