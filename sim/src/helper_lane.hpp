// A second thread for the many short passes of a sweep.
#pragma once

#include <atomic>
#include <cstdint>
#include <thread>

namespace houle::detail {

// for_chunks(n, task) runs task(lane, c) for every chunk c in [0, n) (n < 65536): lane 0 on the
// caller, taking chunks from the front, and lane 1 on the helper, taking them from the back, until
// they meet; it returns when all are done. Which lane runs a chunk depends on timing, so a task's
// result must not.
//
// A sweep makes hundreds of such calls of tens of microseconds each, so a wake-up per call would eat
// the gain: between calls each side spins for a few tens of microseconds before it sleeps. Taking
// chunks rather than a fixed half keeps a busy machine from stalling the caller: when the helper
// does not get a core in time, the caller takes every chunk and waits for none. Taking them from
// the two ends keeps each lane on much the same chunks from call to call, whose data then stays in
// its core's cache (chunks dealt out in turn ran the coast's swell 35 % slower).
class HelperLane {
 public:
  HelperLane() : thread_([this] { serve(); }) {}
  ~HelperLane() {
    stop_.store(true, std::memory_order_relaxed);
    epoch_.store(epoch_.load(std::memory_order_relaxed) + 1, std::memory_order_release);
    epoch_.notify_one();
    thread_.join();
  }
  HelperLane(const HelperLane&) = delete;
  HelperLane& operator=(const HelperLane&) = delete;

  template <class Task>
  void for_chunks(std::uint32_t chunks, Task& task) {
    call_ = [](void* t, int lane, std::uint32_t c) { (*static_cast<Task*>(t))(lane, c); };
    task_ = &task;
    done_.store(0, std::memory_order_relaxed);
    const std::uint32_t e = epoch_.load(std::memory_order_relaxed) + 1;
    work_.store(std::uint64_t(e) << 32 | (chunks & 0xffffu), std::memory_order_release);
    epoch_.store(e, std::memory_order_release);
    epoch_.notify_one();
    take_chunks(0);
    for (std::uint32_t spins = 0, d; (d = done_.load(std::memory_order_acquire)) != chunks; ++spins) {
      if (spins < spin_limit) pause();
      else done_.wait(d, std::memory_order_acquire);
    }
  }

 private:
  static constexpr std::uint32_t spin_limit = 1u << 10;  // pauses, a few tens of microseconds

  static void pause() noexcept {
#if defined(__x86_64__) || defined(__i386__)
    __builtin_ia32_pause();
#elif defined(__aarch64__) || defined(__arm__)
    asm volatile("yield");
#endif
  }

  // Runs chunks of the current call until none is left. A claim is a compare-and-swap on (epoch,
  // front, back), so a claim left over from an earlier call fails.
  void take_chunks(int lane) {
    std::uint64_t w = work_.load(std::memory_order_acquire);
    for (;;) {
      const std::uint32_t front = std::uint32_t(w >> 16) & 0xffffu, back = std::uint32_t(w) & 0xffffu;
      if (front >= back) return;
      const std::uint64_t taken = lane == 0 ? w + (1u << 16) : w - 1;
      if (!work_.compare_exchange_weak(w, taken, std::memory_order_acq_rel, std::memory_order_acquire)) continue;
      call_(task_, lane, lane == 0 ? front : back - 1);
      done_.fetch_add(1, std::memory_order_acq_rel);
      done_.notify_one();
      w = work_.load(std::memory_order_acquire);
    }
  }

  void serve() {
    std::uint32_t seen = 0;
    for (;;) {
      for (std::uint32_t spins = 0; epoch_.load(std::memory_order_acquire) == seen; ++spins) {
        if (spins < spin_limit) pause();
        else epoch_.wait(seen, std::memory_order_acquire);
      }
      seen = epoch_.load(std::memory_order_acquire);
      if (stop_.load(std::memory_order_relaxed)) return;
      take_chunks(1);
    }
  }

  // call_ and task_ are written before a call's epoch is published and read only by a lane that has
  // claimed one of its chunks, which the caller waits for before it writes them again.
  void (*call_)(void*, int, std::uint32_t) = nullptr;
  void* task_ = nullptr;
  std::atomic<std::uint64_t> work_{0};  // epoch << 32 | front << 16 | back: chunks [front, back) are left
  std::atomic<std::uint32_t> done_{0}, epoch_{0};
  std::atomic<bool> stop_{false};
  std::thread thread_;  // last: starts once the rest is initialised
};

}  // namespace houle::detail
