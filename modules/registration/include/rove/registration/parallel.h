#pragma once
/// \file
/// Deterministic block-parallel reduction used by the registration solvers.
/// The index range is cut into fixed blocks whose size does not depend on the
/// number of threads; each block is reduced on its own and the block results
/// are summed in block order. So the result is bit-for-bit the same with 1 or
/// N threads (a property the tests check), and parallelism stays an option of
/// each algorithm, never a process-wide setting.

#include <algorithm>
#include <cstddef>
#include <exception>
#include <thread>
#include <vector>

namespace rove::detail {

/// Points per block: large enough to amortize the scheduling, small enough to
/// balance 2 to 8 threads on clouds of a few thousand points.
inline constexpr std::size_t kReduceBlock = 256;

/// Calls `body(begin, end, acc)` for consecutive blocks of [0, n) on up to
/// `num_threads` threads (≤ 1: the calling thread only) and returns
/// `init` plus the sum of the per-block accumulators in block order.
/// Acc must be default-constructible, copyable and have operator+=.
/// An exception thrown in a block is rethrown on the calling thread.
template <typename Acc, typename Body>
Acc parallel_reduce(std::size_t n, int num_threads, const Acc& zero, Body&& body) {
  const std::size_t blocks = (n + kReduceBlock - 1) / kReduceBlock;
  std::vector<Acc> partial(blocks, zero);
  auto run = [&](std::size_t b) {
    const std::size_t begin = b * kReduceBlock;
    const std::size_t end = std::min(n, begin + kReduceBlock);
    body(begin, end, partial[b]);
  };
  const std::size_t threads =
      std::min<std::size_t>(blocks, static_cast<std::size_t>(std::max(1, num_threads)));
  if (threads <= 1) {
    for (std::size_t b = 0; b < blocks; ++b) run(b);
  } else {
    std::vector<std::exception_ptr> errors(threads);
    std::vector<std::thread> pool;
    pool.reserve(threads - 1);
    auto worker = [&](std::size_t t) {
      try {
        for (std::size_t b = t; b < blocks; b += threads) run(b);
      } catch (...) {
        errors[t] = std::current_exception();
      }
    };
    for (std::size_t t = 1; t < threads; ++t) pool.emplace_back(worker, t);
    worker(0);
    for (auto& th : pool) th.join();
    for (auto& e : errors)
      if (e) std::rethrow_exception(e);
  }
  Acc total = zero;
  for (const auto& p : partial) total += p;
  return total;
}

/// Calls `body(i)` for every i in [0, n) on up to `num_threads` threads;
/// `body` must only write to state owned by index i.
template <typename Body>
void parallel_for(std::size_t n, int num_threads, Body&& body) {
  struct Nothing {
    Nothing& operator+=(const Nothing&) { return *this; }
  };
  parallel_reduce(n, num_threads, Nothing{}, [&](std::size_t b, std::size_t e, Nothing&) {
    for (std::size_t i = b; i < e; ++i) body(i);
  });
}

}  // namespace rove::detail
