// Throughput of the hot pose operators. Each iteration composes a pose from a
// small ring of random inputs so the compiler can neither fold nor hoist the
// work; benchmark::DoNotOptimize keeps the result alive.

#include <array>
#include <cstddef>
#include <random>

#include <benchmark/benchmark.h>

#include "rove/poses/compose.h"

namespace {

constexpr std::size_t kRing = 64;

template <typename T, typename Make>
std::array<T, kRing> make_ring(Make make) {
  std::mt19937_64 rng(12345);
  std::uniform_real_distribution<double> u(-3.0, 3.0);
  std::array<T, kRing> ring;
  for (auto& v : ring) v = make(rng, u);
  return ring;
}

std::array<rove::Pose3, kRing> pose3_ring() {
  return make_ring<rove::Pose3>([](auto& rng, auto& u) {
    return rove::Pose3(u(rng), u(rng), u(rng), u(rng), 0.5 * u(rng), u(rng));
  });
}

void BM_Pose3PlusPose3(benchmark::State& state) {
  const auto a = pose3_ring();
  const auto b = pose3_ring();
  std::size_t i = 0;
  for (auto _ : state) {
    rove::Pose3 c = a[i % kRing] + b[(i + 7) % kRing];
    benchmark::DoNotOptimize(c);
    ++i;
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_Pose3PlusPose3);

void BM_Pose3PlusPoint3(benchmark::State& state) {
  const auto a = pose3_ring();
  const auto p = make_ring<rove::Point3>(
      [](auto& rng, auto& u) { return rove::Point3(u(rng), u(rng), u(rng)); });
  std::size_t i = 0;
  for (auto _ : state) {
    rove::Point3 g = a[i % kRing] + p[(i + 7) % kRing];
    benchmark::DoNotOptimize(g);
    ++i;
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_Pose3PlusPoint3);

void BM_Pose3MinusPose3(benchmark::State& state) {
  const auto a = pose3_ring();
  const auto b = pose3_ring();
  std::size_t i = 0;
  for (auto _ : state) {
    rove::Pose3 c = a[i % kRing] - b[(i + 7) % kRing];
    benchmark::DoNotOptimize(c);
    ++i;
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_Pose3MinusPose3);

void BM_Pose2PlusPose2(benchmark::State& state) {
  const auto a = make_ring<rove::Pose2>(
      [](auto& rng, auto& u) { return rove::Pose2(u(rng), u(rng), u(rng)); });
  std::size_t i = 0;
  for (auto _ : state) {
    rove::Pose2 c = a[i % kRing] + a[(i + 7) % kRing];
    benchmark::DoNotOptimize(c);
    ++i;
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_Pose2PlusPose2);

}  // namespace

BENCHMARK_MAIN();
