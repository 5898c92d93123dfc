// The thread pool (thread_pool.hpp): every range of a call run once, on a lane of the pool, aligned to
// the grain, however many ranges; many short calls in a row, none allocating.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <memory>
#include <vector>

#include "allocation_counter.hpp"
#include "houle/runtime/thread_pool.hpp"

namespace {

using houle::detail::ThreadPool;

std::unique_ptr<ThreadPool> make_pool(unsigned threads) {
  auto pool = ThreadPool::create(threads);
  EXPECT_TRUE(pool.ok());
  return std::move(pool.value());
}

TEST(ThreadPool, EveryRangeOnceAlignedToTheGrain) {
  // 200003 ranges of one item: more than a claim can number (2^16), so a claim holds several.
  for (unsigned threads : {1u, 2u, 3u}) {
    std::unique_ptr<ThreadPool> pool = make_pool(threads);
    ASSERT_EQ(pool->size(), threads);
    for (std::size_t n : {std::size_t(0), std::size_t(1), std::size_t(7), std::size_t(1000), std::size_t(200003)}) {
      for (std::size_t grain : {std::size_t(1), std::size_t(3), std::size_t(16)}) {
        std::vector<std::atomic<int>> runs(n);
        std::atomic<int> misplaced{0};
        pool->for_ranges(n, grain, [&](std::size_t begin, std::size_t end, unsigned lane) {
          if (begin % grain != 0 || end != std::min(n, begin + grain) || lane >= threads) ++misplaced;
          for (std::size_t i = begin; i < end; ++i) runs[i].fetch_add(1, std::memory_order_relaxed);
        });
        EXPECT_EQ(misplaced.load(), 0) << threads << " threads, n " << n << ", grain " << grain;
        EXPECT_EQ(std::count_if(runs.begin(), runs.end(), [](const std::atomic<int>& r) { return r.load() != 1; }), 0)
            << threads << " threads, n " << n << ", grain " << grain;
      }
    }
  }
}

TEST(ThreadPool, ZeroThreadsIsTheCallerAlone) {
  std::unique_ptr<ThreadPool> pool = make_pool(0);
  ASSERT_EQ(pool->size(), 1u);
  unsigned lanes_used = 0;
  pool->for_ranges(10, 2, [&](std::size_t, std::size_t, unsigned lane) { lanes_used |= 1u << lane; });
  EXPECT_EQ(lanes_used, 1u);
}

TEST(ThreadPool, ManyShortCallsAllocateNothing) {
  // As the ray tracer calls it: hundreds of short passes in a row, each writing per-lane sums.
  std::unique_ptr<ThreadPool> pool = make_pool(2);
  struct alignas(64) Sum {
    long value = 0;
  };
  Sum sums[2];
  long expected = 0, total = 0;
  long allocations = 0;
  {
    houle::test::AllocationCounter counter;
    for (int call = 0; call < 2000; ++call) {
      sums[0].value = sums[1].value = 0;
      pool->for_ranges(64 + std::size_t(call % 5), 4, [&](std::size_t begin, std::size_t end, unsigned lane) {
        for (std::size_t i = begin; i < end; ++i) sums[lane].value += long(i) * call;
      });
      const long n = 64 + call % 5;
      expected += n * (n - 1) / 2 * call;
      total += sums[0].value + sums[1].value;
    }
    allocations = counter.count();
  }
  EXPECT_EQ(total, expected);
  EXPECT_EQ(allocations, 0);
}

}  // namespace
