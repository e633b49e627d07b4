// One weighting step of Monte-Carlo localization with 40,000 particles:
// rove vs MRPT 2.5.8 on the same grid (MRPT's localization demo: the grid of
// localization_demo.ini's [MetricMap], 6 cm, built from
// localization_demo.simplemap.gz by each library), the same scan (the log's
// second step) and the same 40,000 poses (uniform in the demo's initial box
// x ∈ [−10, 10] m, y ∈ [−15, −5] m, any heading). Likelihood field (Thrun),
// LF_decimation 20 as the config says. MRPT: CMultiMetricMap::
// computeObservationsLikelihood per particle, as its CMonteCarloLocalization2D
// weighs (its likelihood cache warmed first); rove: GridLikelihoodModel on
// SE2d poses, as MonteCarloLocalization weighs, on 1 and 2 threads.
// Reported: particles/s and particles·rays/s (rays: the scan's 361 rays;
// points evaluated after decimation are 1 in 20 of the valid ones).
#include <benchmark/benchmark.h>

#include <mrpt/config/CConfigFile.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/maps/CMultiMetricMap.h>
#include <mrpt/maps/CSimpleMap.h>
#include <mrpt/maps/TMetricMapInitializer.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CRawlog.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/serialization/CArchive.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <numbers>
#include <variant>
#include <vector>

#include "rove/bayes/random.h"
#include "rove/core/ini.h"
#include "rove/core/parallel.h"
#include "rove/io/any_rawlog.h"
#include "rove/maps/grid_likelihood.h"
#include "rove/maps/metric_map_occupancy_grid.h"
#include "rove/obs/range_scan_2d.h"
#include "rove/slam/pf_localization_run.h"

namespace {

const char* kConfig = ROVE_SOURCE_DATA_DIR "/mrpt/localization_demo.ini";
const char* kMap = ROVE_SOURCE_DATA_DIR "/mrpt/localization_demo.simplemap.gz";
const char* kRawlog = ROVE_SOURCE_DATA_DIR "/mrpt/localization_demo.rawlog";
constexpr std::size_t kParticles = 40000;

const std::vector<rove::SE2d>& poses() {
  static const std::vector<rove::SE2d> p = [] {
    std::vector<rove::SE2d> v;
    rove::Rng rng(2024);
    for (std::size_t i = 0; i < kParticles; ++i) {
      const double x = rng.uniform(-10, 10), y = rng.uniform(-15, -5);
      v.emplace_back(x, y, rng.uniform(-std::numbers::pi, std::numbers::pi));
    }
    return v;
  }();
  return p;
}

struct Mrpt {
  mrpt::maps::CMultiMetricMap map;
  mrpt::obs::CSensoryFrame::Ptr frame;
  std::vector<mrpt::poses::CPose3D> poses;
};

Mrpt& mrpt_side() {
  static Mrpt m = [] {
    Mrpt m;
    mrpt::config::CConfigFile cfg(kConfig);
    mrpt::maps::TSetOfMetricMapInitializers inits;
    inits.loadFromConfigFile(cfg, "MetricMap");
    m.map.setListOfMaps(inits);
    mrpt::maps::CSimpleMap sm;
    {
      mrpt::io::CFileGZInputStream f(kMap);
      mrpt::serialization::archiveFrom(f) >> sm;
    }
    m.map.loadFromProbabilisticPosesAndObservations(sm);
    mrpt::io::CFileGZInputStream f(kRawlog);
    auto ar = mrpt::serialization::archiveFrom(f);
    mrpt::obs::CActionCollection::Ptr acts;
    mrpt::obs::CObservation::Ptr obs;
    size_t idx = 0;
    for (int step = 0; step < 2; ++step) {
      if (!mrpt::obs::CRawlog::getActionObservationPairOrObservation(ar, acts, m.frame, obs, idx)) {
        std::fprintf(stderr, "cannot read %s\n", kRawlog);
        std::exit(1);
      }
    }
    for (const auto& p : poses()) {
      m.poses.emplace_back(p.translation().x(), p.translation().y(), 0.0, p.angle(), 0.0, 0.0);
    }
    return m;
  }();
  return m;
}

struct Rove {
  std::shared_ptr<rove::MultiMetricMap> map;
  std::unique_ptr<rove::GridLikelihoodModel<std::int8_t>> model;
  rove::PreparedGridScan scan;
  std::size_t rays = 0;
};

Rove& rove_side() {
  static Rove r = [] {
    Rove r;
    rove::PfLocalizationConfig cfg =
        rove::load_pf_localization_config(rove::IniFile::load(kConfig));
    cfg.map_file = kMap;
    r.map = std::make_shared<rove::MultiMetricMap>(std::move(cfg.map));
    rove::load_localization_map(cfg, *r.map);
    const auto* g =
        dynamic_cast<const rove::OccupancyGridMetricMap*>(r.map->entries().front().map.get());
    r.model = std::make_unique<rove::GridLikelihoodModel<std::int8_t>>(
        g->grid(), g->likelihood_options, g->insert_options);
    const rove::AnyRawlog log = rove::load_any_rawlog(kRawlog);
    int frames = 0;
    for (const auto& e : log.entries) {
      const auto* f = std::get_if<std::shared_ptr<const rove::SensoryFrame>>(&e);
      if (f == nullptr || ++frames < 2) continue;
      const auto scan = (*f)->find<rove::RangeScan2D>();
      r.scan = r.model->prepare(*scan);
      r.rays = scan->size();
      break;
    }
    return r;
  }();
  return r;
}

// The two libraries must compute the same log-likelihoods (as checked in
// rove's grid tests): report the largest difference once.
void check_agreement() {
  Mrpt& m = mrpt_side();
  Rove& r = rove_side();
  const auto& p = poses();
  double worst = 0.0;
  for (std::size_t i = 0; i < p.size(); i += 97) {
    const double a = m.map.computeObservationsLikelihood(*m.frame, m.poses[i]);
    const double b = r.model->log_likelihood(r.scan, p[i]);
    worst = std::max(worst, std::abs(a - b));
  }
  std::printf("largest |rove - MRPT| log-likelihood over %zu poses: %.3g (scan of %zu rays)\n",
              p.size() / 97 + 1, worst, r.rays);
}

void counters(benchmark::State& st) {
  const double n = static_cast<double>(st.iterations() * kParticles);
  st.counters["particles/s"] = benchmark::Counter(n, benchmark::Counter::kIsRate);
  st.counters["particle_rays/s"] =
      benchmark::Counter(n * static_cast<double>(rove_side().rays), benchmark::Counter::kIsRate);
}

void BM_Weighting40k_Mrpt(benchmark::State& st) {
  Mrpt& m = mrpt_side();
  std::vector<double> w(kParticles);
  for (std::size_t i = 0; i < kParticles; ++i) {  // warm MRPT's lazily filled cache
    w[i] = m.map.computeObservationsLikelihood(*m.frame, m.poses[i]);
  }
  for (auto _ : st) {
    for (std::size_t i = 0; i < kParticles; ++i) {
      w[i] = m.map.computeObservationsLikelihood(*m.frame, m.poses[i]);
    }
    benchmark::DoNotOptimize(w.data());
  }
  counters(st);
}

void BM_Weighting40k_Rove(benchmark::State& st) {
  Rove& r = rove_side();
  const auto& p = poses();
  std::vector<double> w(kParticles);
  rove::ThreadTeam team(static_cast<int>(st.range(0)));
  for (auto _ : st) {
    rove::parallel_for(kParticles, team,
                       [&](std::size_t i) { w[i] = r.model->log_likelihood(r.scan, p[i]); });
    benchmark::DoNotOptimize(w.data());
  }
  counters(st);
}

BENCHMARK(BM_Weighting40k_Mrpt)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_Weighting40k_Rove)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  check_agreement();
  benchmark::RunSpecifiedBenchmarks();
  return 0;
}
