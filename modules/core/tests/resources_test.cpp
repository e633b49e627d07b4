#include <gtest/gtest.h>

#include <csignal>
#include <cstdint>
#include <limits>
#include <thread>

#include "rove/core/error.h"
#include "rove/core/interrupt.h"
#include "rove/core/memory_budget.h"
#include "rove/core/parallel.h"

namespace {

TEST(ThreadCount, RefusesAbsurdRequestsAndResolvesZero) {
  EXPECT_EQ(rove::resolve_thread_count(1), 1);
  EXPECT_EQ(rove::resolve_thread_count(rove::kMaxThreads), rove::kMaxThreads);
  EXPECT_GE(rove::resolve_thread_count(0), 1);
  EXPECT_LE(rove::resolve_thread_count(0), rove::kMaxThreads);
  EXPECT_THROW(rove::resolve_thread_count(100000, "--threads"), rove::InvalidArgument);
  EXPECT_THROW(rove::resolve_thread_count(-1, "--threads"), rove::InvalidArgument);
  try {
    rove::resolve_thread_count(100000, "--threads");
  } catch (const rove::InvalidArgument& e) {
    EXPECT_NE(e.message().find("--threads"), std::string::npos) << e.message();
  }
}

TEST(ParallelReduce, SameSumOnOneAndManyThreads) {
  auto sum = [](int threads) {
    rove::ThreadTeam team(threads);
    return rove::parallel_reduce(100003, team, 0.0, [](std::size_t b, std::size_t e, double& acc) {
      for (std::size_t i = b; i < e; ++i) acc += 1.0 / static_cast<double>(i + 1);
    });
  };
  const double one = sum(1);
  EXPECT_EQ(sum(2), one);
  EXPECT_EQ(sum(7), one);
}

TEST(MemoryBudget, RefusesOversizedRequestsNamingTheCulprit) {
  const std::uint64_t budget = rove::memory_budget_bytes();
  EXPECT_GT(budget, 0u);
  EXPECT_NO_THROW(rove::check_memory_budget(1024, "small"));
  try {
    rove::check_memory_budget(std::numeric_limits<std::uint64_t>::max(), "map.png: 16000 × 16000 cells");
    FAIL();
  } catch (const rove::ResourceError& e) {
    EXPECT_NE(e.message().find("map.png: 16000 × 16000 cells"), std::string::npos) << e.message();
  }
}

TEST(MemoryBudget, CheckedBytesSaturates) {
  EXPECT_EQ(rove::checked_bytes(16000ull * 16000ull, 24), 6144000000ull);
  EXPECT_EQ(rove::checked_bytes(std::numeric_limits<std::uint64_t>::max() / 2, 3),
            std::numeric_limits<std::uint64_t>::max());
  EXPECT_EQ(rove::format_bytes(6144000000ull), "6.1 GB");
}

TEST(Interrupt, FirstSignalSetsTheFlagAndThrowsAtTheNextCheck) {
  rove::install_interrupt_handler();
  rove::reset_interrupted();
  EXPECT_NO_THROW(rove::throw_if_interrupted());
  std::raise(SIGINT);
  EXPECT_TRUE(rove::interrupted());
  EXPECT_THROW(rove::throw_if_interrupted(), rove::Interrupted);
  rove::reset_interrupted();
  EXPECT_FALSE(rove::interrupted());
}

}  // namespace
