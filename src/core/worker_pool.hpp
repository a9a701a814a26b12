#pragma once
/// A few threads of the world's own for the per-pair stages of a prediction (private to the
/// core). The caller runs part 0 of a job itself and the workers the others, so a job of n
/// parts keeps n threads busy with n - 1 workers; run() returns when every part is done.
/// Workers sleep on a condition variable between jobs (waking one costs some microseconds,
/// hence jobs are only worth it for thousands of pairs). Nothing is allocated per job.

#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <thread>
#include <vector>

namespace workspace_proximity {

class WorkerPool {
 public:
  /// One part of a job: `part` in [0, parts).
  using Task = void (*)(void* context, int part);

  /// `workers` threads (0: run() does every part on the caller), started here.
  explicit WorkerPool(int workers);
  ~WorkerPool();  ///< stops and joins the workers (a job never outlives run())
  WorkerPool(const WorkerPool&) = delete;
  WorkerPool& operator=(const WorkerPool&) = delete;

  int workers() const { return static_cast<int>(threads_.size()); }

  /// Runs task(context, part) for every part in [0, parts), at most workers() + 1 parts:
  /// part 0 on the calling thread, part k on worker k - 1. The task must not throw (catch in
  /// it and hand the error back through the context).
  void run(int parts, Task task, void* context);

 private:
  void loop(int index);

  std::vector<std::thread> threads_;
  std::mutex mutex_;
  std::condition_variable start_;
  std::condition_variable done_;
  std::uint64_t job_ = 0;  // jobs started so far (a worker runs each job once)
  int parts_ = 0;
  int pending_ = 0;        // worker parts of the job under way not finished yet
  Task task_ = nullptr;
  void* context_ = nullptr;
  bool stop_ = false;
};

}  // namespace workspace_proximity
