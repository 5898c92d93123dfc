#include "houle/runtime/thread_pool.hpp"

#include <string>
#include <system_error>

#include "houle/runtime/assert.hpp"

namespace houle::detail {

Expected<std::unique_ptr<ThreadPool>> ThreadPool::create(unsigned threads) {
  std::unique_ptr<ThreadPool> pool(new ThreadPool());
  pool->size_ = threads == 0 ? 1 : threads;
  pool->workers_.reserve(pool->size_ - 1);
  // std::thread reports failure by throwing; errors leave the library as values.
  try {
    for (unsigned w = 1; w < pool->size_; ++w) {
      ThreadPool* p = pool.get();
      pool->workers_.emplace_back([p, w] { p->worker_loop(w); });
    }
  } catch (const std::system_error& e) {
    pool->size_ = unsigned(pool->workers_.size()) + 1;  // the destructor joins the ones started
    return Error{"threads", std::string("could not start a worker thread: ") + e.what()};
  }
  return pool;
}

ThreadPool::~ThreadPool() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  start_.notify_all();
  for (std::thread& t : workers_) t.join();
}

void ThreadPool::run(Task task, void* context) noexcept {
  HOULE_ASSERT(task != nullptr, "ThreadPool::run: a task");
  if (!workers_.empty()) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      task_ = task;
      context_ = context;
      pending_ = unsigned(workers_.size());
      ++generation_;
    }
    start_.notify_all();
  }
  task(context, 0);
  if (!workers_.empty()) {
    std::unique_lock<std::mutex> lock(mutex_);
    done_.wait(lock, [this] { return pending_ == 0; });
  }
}

void ThreadPool::worker_loop(unsigned index) noexcept {
  std::uint64_t seen = 0;
  for (;;) {
    Task task = nullptr;
    void* context = nullptr;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      start_.wait(lock, [&] { return stop_ || generation_ != seen; });
      if (stop_) return;
      seen = generation_;
      task = task_;
      context = context_;
    }
    task(context, index);
    bool last = false;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      last = --pending_ == 0;
    }
    if (last) done_.notify_one();
  }
}

}  // namespace houle::detail
