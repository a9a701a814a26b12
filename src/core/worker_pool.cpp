#include "worker_pool.hpp"

#include <algorithm>
#include <stdexcept>

namespace workspace_proximity {

WorkerPool::WorkerPool(int workers) {
  if (workers < 0) throw std::invalid_argument("WorkerPool: negative worker count");
  threads_.reserve(static_cast<std::size_t>(workers));
  for (int i = 0; i < workers; ++i) threads_.emplace_back([this, i] { loop(i); });
}

WorkerPool::~WorkerPool() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  start_.notify_all();
  for (std::thread& t : threads_) t.join();
}

void WorkerPool::run(int parts, Task task, void* context) {
  parts = std::max(1, std::min(parts, workers() + 1));
  if (parts == 1) {
    task(context, 0);
    return;
  }
  {
    std::lock_guard<std::mutex> lock(mutex_);
    task_ = task;
    context_ = context;
    parts_ = parts;
    pending_ = parts - 1;
    ++job_;
  }
  start_.notify_all();
  task(context, 0);
  std::unique_lock<std::mutex> lock(mutex_);
  done_.wait(lock, [this] { return pending_ == 0; });
}

void WorkerPool::loop(int index) {
  std::uint64_t seen = 0;
  for (;;) {
    Task task;
    void* context;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      start_.wait(lock, [&] { return stop_ || job_ != seen; });
      if (stop_) return;
      seen = job_;
      // Workers beyond the job's parts sit it out.
      if (index + 1 >= parts_) continue;
      task = task_;
      context = context_;
    }
    task(context, index + 1);
    {
      std::lock_guard<std::mutex> lock(mutex_);
      --pending_;
      if (pending_ == 0) done_.notify_one();
    }
  }
}

}  // namespace workspace_proximity
