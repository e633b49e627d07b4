#pragma once
/// \file
/// Threads for every rove module: one persistent team per solver run, and a
/// deterministic block-parallel reduction over it.
/// The index range is cut into fixed blocks whose size does not depend on the
/// number of threads; each block is reduced on its own and the block results
/// are summed in block order. So the result is bit-for-bit the same with 1 or
/// N threads (a property the tests check), and parallelism stays an option of
/// each algorithm, never a process-wide setting.
///
/// A solver that reduces many times (an iteration loop) creates one
/// ThreadTeam for its run and passes it to every reduction, so threads are
/// started once per call of the solver, not once per pass.

#include <algorithm>
#include <condition_variable>
#include <cstddef>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace rove {

/// The most threads any rove algorithm starts. Requests above it are refused
/// by resolve_thread_count (a typo such as --threads 100000 must not start
/// tens of thousands of threads).
inline constexpr int kMaxThreads = 256;

/// The thread count to use for a request: `requested` itself when in
/// [1, kMaxThreads]; 0 means "all hardware threads" (at least 1). Anything
/// else throws rove::InvalidArgument naming `what` ("--threads",
/// "[ICP] num_threads") and the accepted range.
int resolve_thread_count(int requested, const char* what = "num_threads");


/// Points per block: large enough to amortize the scheduling, small enough to
/// balance 2 to 8 threads on clouds of a few thousand points.
inline constexpr std::size_t kReduceBlock = 256;

/// num_threads − 1 worker threads that sleep between jobs; the calling thread
/// is member 0. Not copyable; one job at a time (not thread-safe itself).
class ThreadTeam {
 public:
  /// Starts max(num_threads, 1) − 1 workers.
  explicit ThreadTeam(int num_threads) : size_(std::max(1, num_threads)) {
    workers_.reserve(static_cast<std::size_t>(size_ - 1));
    try {
      for (int t = 1; t < size_; ++t) workers_.emplace_back([this, t] { loop(t); });
    } catch (...) {
      // The system refused a thread: stop those already started, then report.
      stop_workers();
      throw;
    }
  }
  ThreadTeam(const ThreadTeam&) = delete;
  ThreadTeam& operator=(const ThreadTeam&) = delete;
  ~ThreadTeam() { stop_workers(); }
  /// Members, ≥ 1.
  int size() const noexcept { return size_; }
  /// Calls job(t) for every member t in [0, size()) — t = 0 on the calling
  /// thread — and returns when all are done. The first exception thrown by a
  /// member is rethrown here.
  void run(const std::function<void(int)>& job) {
    if (size_ == 1) {
      job(0);
      return;
    }
    errors_.assign(static_cast<std::size_t>(size_), nullptr);
    {
      std::lock_guard lock(mutex_);
      job_ = &job;
      pending_ = size_ - 1;
      ++generation_;
    }
    wake_.notify_all();
    try {
      job(0);
    } catch (...) {
      errors_[0] = std::current_exception();
    }
    {
      std::unique_lock lock(mutex_);
      done_.wait(lock, [this] { return pending_ == 0; });
      job_ = nullptr;
    }
    for (auto& e : errors_)
      if (e) std::rethrow_exception(e);
  }

 private:
  void stop_workers() {
    {
      std::lock_guard lock(mutex_);
      stop_ = true;
    }
    wake_.notify_all();
    for (auto& w : workers_) w.join();
  }
  void loop(int t) {
    std::size_t seen = 0;
    while (true) {
      const std::function<void(int)>* job = nullptr;
      {
        std::unique_lock lock(mutex_);
        wake_.wait(lock, [&] { return stop_ || generation_ != seen; });
        if (stop_) return;
        seen = generation_;
        job = job_;
      }
      try {
        (*job)(t);
      } catch (...) {
        errors_[static_cast<std::size_t>(t)] = std::current_exception();
      }
      {
        std::lock_guard lock(mutex_);
        --pending_;
      }
      done_.notify_one();
    }
  }

  int size_;
  std::vector<std::thread> workers_;
  std::mutex mutex_;
  std::condition_variable wake_, done_;
  const std::function<void(int)>* job_ = nullptr;
  std::size_t generation_ = 0;
  int pending_ = 0;
  bool stop_ = false;
  std::vector<std::exception_ptr> errors_;
};

/// Calls `body(begin, end, acc)` for consecutive blocks of [0, n), block b on
/// member b mod team.size(), and returns `zero` plus the sum of the per-block
/// accumulators in block order. Acc must be copyable and have operator+=.
/// An exception thrown in a block is rethrown on the calling thread.
template <typename Acc, typename Body>
Acc parallel_reduce(std::size_t n, ThreadTeam& team, const Acc& zero, Body&& body) {
  const std::size_t blocks = (n + kReduceBlock - 1) / kReduceBlock;
  auto run = [&](std::size_t b, Acc& acc) {
    const std::size_t begin = b * kReduceBlock;
    const std::size_t end = std::min(n, begin + kReduceBlock);
    body(begin, end, acc);
  };
  Acc total = zero;
  const std::size_t threads = std::min<std::size_t>(blocks, static_cast<std::size_t>(team.size()));
  if (threads <= 1) {
    // Same association as the parallel path: each block from zero, then
    // added in order.
    for (std::size_t b = 0; b < blocks; ++b) {
      Acc partial = zero;
      run(b, partial);
      total += partial;
    }
    return total;
  }
  std::vector<Acc> partial(blocks, zero);
  team.run([&](int t) {
    for (std::size_t b = static_cast<std::size_t>(t); b < blocks; b += threads) run(b, partial[b]);
  });
  for (const auto& p : partial) total += p;
  return total;
}

/// As above with a team of `num_threads` started for this call only.
template <typename Acc, typename Body>
Acc parallel_reduce(std::size_t n, int num_threads, const Acc& zero, Body&& body) {
  const std::size_t blocks = (n + kReduceBlock - 1) / kReduceBlock;
  ThreadTeam team(static_cast<int>(
      std::min<std::size_t>(blocks, static_cast<std::size_t>(std::max(1, num_threads)))));
  return parallel_reduce(n, team, zero, std::forward<Body>(body));
}

/// Calls `body(i)` for every i in [0, n) on the team's threads; `body` must
/// only write to state owned by index i.
template <typename Body>
void parallel_for(std::size_t n, ThreadTeam& team, Body&& body) {
  struct Nothing {
    Nothing& operator+=(const Nothing&) { return *this; }
  };
  parallel_reduce(n, team, Nothing{}, [&](std::size_t b, std::size_t e, Nothing&) {
    for (std::size_t i = b; i < e; ++i) body(i);
  });
}

/// As above with a team of `num_threads` started for this call only.
template <typename Body>
void parallel_for(std::size_t n, int num_threads, Body&& body) {
  ThreadTeam team(std::max(1, num_threads));
  parallel_for(n, team, std::forward<Body>(body));
}

}  // namespace rove
