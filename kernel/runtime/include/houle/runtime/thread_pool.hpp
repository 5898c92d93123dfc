// A persistent pool of worker threads for the frame loop (docs/rendering.md 2.3: row bands handed out by an
// atomic counter, no thread creation per frame). run() hands the same task to every worker and to the
// caller, which counts as worker 0, and returns when all have finished; how the work is split is the
// task's business (an atomic row counter in the renderer). run() allocates nothing.
#pragma once
#include <condition_variable>
#include <cstdint>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

#include "houle/runtime/expected.hpp"

namespace houle::detail {

class ThreadPool {
 public:
  using Task = void (*)(void* context, unsigned worker) noexcept;

  /// `threads` workers counting the caller (0 counts as 1), started now. Fails when the system cannot
  /// start a thread.
  static Expected<std::unique_ptr<ThreadPool>> create(unsigned threads);
  ~ThreadPool();
  ThreadPool(const ThreadPool&) = delete;
  ThreadPool& operator=(const ThreadPool&) = delete;

  unsigned size() const noexcept { return size_; }
  /// task(context, w) once for every w in [0, size()), w = 0 on the calling thread; returns when all
  /// have returned. Not reentrant: one run() at a time.
  void run(Task task, void* context) noexcept;

 private:
  ThreadPool() = default;
  void worker_loop(unsigned index) noexcept;

  unsigned size_ = 1;
  std::vector<std::thread> workers_;
  std::mutex mutex_;
  std::condition_variable start_, done_;
  std::uint64_t generation_ = 0;  // bumped by run(); workers run once per value
  unsigned pending_ = 0;          // workers (not the caller) still running the current task
  bool stop_ = false;
  Task task_ = nullptr;
  void* context_ = nullptr;
};

}  // namespace houle::detail
