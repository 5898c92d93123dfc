#include "houle/runtime/thread_pool.hpp"

#include <algorithm>
#include <string>
#include <system_error>

#include "houle/runtime/assert.hpp"

namespace houle::detail {
namespace {

constexpr std::uint32_t spin_limit = 1u << 10;  // pauses, a few tens of microseconds
constexpr std::size_t max_claims = 0xffff;      // front and back are 16 bits in work_

void pause() noexcept {
#if defined(__x86_64__) || defined(__i386__)
  __builtin_ia32_pause();
#elif defined(__aarch64__) || defined(__arm__)
  asm volatile("yield");
#endif
}

}  // namespace

Expected<std::unique_ptr<ThreadPool>> ThreadPool::create(unsigned threads) {
  std::unique_ptr<ThreadPool> pool(new ThreadPool());
  const unsigned lanes = threads == 0 ? 1 : threads;
  pool->workers_.reserve(lanes - 1);
  // std::thread reports failure by throwing; errors leave the library as values.
  try {
    for (unsigned lane = 1; lane < lanes; ++lane) {
      ThreadPool* p = pool.get();
      pool->workers_.emplace_back([p, lane] { p->serve(lane); });
    }
  } catch (const std::system_error& e) {
    return Error{"threads", std::string("could not start a worker thread: ") + e.what()};  // the destructor joins the ones started
  }
  return pool;
}

ThreadPool::~ThreadPool() {
  stop_.store(true, std::memory_order_relaxed);
  epoch_.store(epoch_.load(std::memory_order_relaxed) + 1, std::memory_order_release);
  epoch_.notify_all();
  for (std::thread& t : workers_) t.join();
}

void ThreadPool::run(Call call, void* task, std::size_t n, std::size_t grain) noexcept {
  HOULE_ASSERT(call != nullptr && grain > 0, "ThreadPool::run: a task and a grain of at least one item");
  const std::size_t count = (n + grain - 1) / grain;
  if (count == 0) return;
  if (workers_.empty()) {
    for (std::size_t r = 0; r < count; ++r) call(task, r * grain, std::min(n, (r + 1) * grain), 0);
    return;
  }
  const std::size_t per_claim = (count + max_claims - 1) / max_claims;
  const auto claims = std::uint32_t((count + per_claim - 1) / per_claim);
  ranges_ = Ranges{call, task, n, grain, count, per_claim};
  done_.store(0, std::memory_order_relaxed);
  const std::uint32_t e = epoch_.load(std::memory_order_relaxed) + 1;
  work_.store(std::uint64_t(e) << 32 | claims, std::memory_order_release);
  epoch_.store(e, std::memory_order_release);
  epoch_.notify_all();
  take_claims(0);
  for (std::uint32_t spins = 0, d; (d = done_.load(std::memory_order_acquire)) != claims; ++spins) {
    if (spins < spin_limit) pause();
    else done_.wait(d, std::memory_order_acquire);
  }
}

// Runs claims of the current call until none is left. A claim is a compare-and-swap on (epoch, front,
// back), so a claim left over from an earlier call fails.
void ThreadPool::take_claims(unsigned lane) noexcept {
  std::uint64_t w = work_.load(std::memory_order_acquire);
  for (;;) {
    const std::uint32_t front = std::uint32_t(w >> 16) & 0xffffu, back = std::uint32_t(w) & 0xffffu;
    if (front >= back) return;
    const std::uint64_t taken = lane == 0 ? w + (1u << 16) : w - 1;
    if (!work_.compare_exchange_weak(w, taken, std::memory_order_acq_rel, std::memory_order_acquire)) continue;
    const Ranges& c = ranges_;
    const std::size_t claim = lane == 0 ? front : back - 1;
    for (std::size_t r = claim * c.per_claim, end = std::min(c.count, r + c.per_claim); r < end; ++r) {
      c.call(c.task, r * c.grain, std::min(c.n, (r + 1) * c.grain), lane);
    }
    done_.fetch_add(1, std::memory_order_acq_rel);
    done_.notify_one();
    w = work_.load(std::memory_order_acquire);
  }
}

void ThreadPool::serve(unsigned lane) noexcept {
  std::uint32_t seen = 0;
  for (;;) {
    for (std::uint32_t spins = 0; epoch_.load(std::memory_order_acquire) == seen; ++spins) {
      if (spins < spin_limit) pause();
      else epoch_.wait(seen, std::memory_order_acquire);
    }
    seen = epoch_.load(std::memory_order_acquire);
    if (stop_.load(std::memory_order_relaxed)) return;
    take_claims(lane);
  }
}

}  // namespace houle::detail
