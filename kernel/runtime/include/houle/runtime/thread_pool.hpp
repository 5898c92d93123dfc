// The one way houle runs work on several threads: a pool started once (docs/rendering.md 2.3: no thread
// creation per frame), whose for_ranges() splits [0, n) into ranges of `grain` items that the lanes
// claim until none is left. The calling thread is lane 0 and takes part. for_ranges() allocates
// nothing.
//
// The renderer calls it once per frame (rows of a few hundred microseconds each), the ray tracer
// hundreds of times per sweep (passes of tens of microseconds), so a wake-up per call would eat the
// tracer's gain: between calls every side spins for a few tens of microseconds before it sleeps.
// Ranges are claimed rather than dealt out as fixed shares so that a busy machine does not stall the
// caller: when a worker does not get a core in time, the caller takes every range and waits for
// none. Lane 0 claims from the front and the others from the back, which keeps each lane on much the
// same ranges from call to call, whose data then stays in its core's cache (ranges dealt out in turn
// ran the coast's swell 35 % slower).
#pragma once
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <thread>
#include <type_traits>
#include <vector>

#include "houle/runtime/expected.hpp"

namespace houle::detail {

class ThreadPool {
 public:
  /// `threads` lanes counting the caller (0 counts as 1), started now. Fails when the system cannot
  /// start a thread.
  static Expected<std::unique_ptr<ThreadPool>> create(unsigned threads);
  ~ThreadPool();
  ThreadPool(const ThreadPool&) = delete;
  ThreadPool& operator=(const ThreadPool&) = delete;

  unsigned size() const noexcept { return unsigned(workers_.size()) + 1; }

  /// task(begin, end, lane) for every range [k grain, min(n, (k + 1) grain)) of [0, n) (grain 0
  /// counts as 1), lane in [0, size()), lane 0 on the calling thread; returns when all have returned.
  /// Which lane runs a range depends on timing, so a task's result must not; a lane runs one range at
  /// a time, so per-lane scratch indexed by `lane` needs no lock. The task must not throw. Not
  /// reentrant: one call at a time, and none from inside one of this pool's tasks (a task may call
  /// another pool: trace_wave_field gives each worker a pool of its own).
  template <class Task>
  void for_ranges(std::size_t n, std::size_t grain, Task&& task) noexcept {
    using T = std::remove_reference_t<Task>;
    run([](void* t, std::size_t begin, std::size_t end, unsigned lane) noexcept { (*static_cast<T*>(t))(begin, end, lane); },
        const_cast<void*>(static_cast<const void*>(&task)), n, grain == 0 ? 1 : grain);
  }

 private:
  using Call = void (*)(void* task, std::size_t begin, std::size_t end, unsigned lane) noexcept;
  struct Ranges {
    Call call;
    void* task;
    std::size_t n, grain, count;
    std::size_t per_claim;  // ranges per claim: claims are numbered below 2^16
  };

  ThreadPool() = default;
  void run(Call call, void* task, std::size_t n, std::size_t grain) noexcept;
  void take_claims(unsigned lane) noexcept;
  void serve(unsigned lane) noexcept;

  // ranges_ is written before a call's epoch is published and read only by a lane that has claimed
  // a range of it, which the caller waits for before it writes ranges_ again.
  Ranges ranges_{};
  std::atomic<std::uint64_t> work_{0};  // epoch << 32 | front << 16 | back: claims [front, back) are left
  std::atomic<std::uint32_t> done_{0}, epoch_{0};
  std::atomic<bool> stop_{false};
  std::vector<std::thread> workers_;
};

}  // namespace houle::detail
