// The world's worker pool (src/core/worker_pool.hpp): every part of every job runs exactly
// once, on the caller (part 0) and the workers, and run() returns only when all are done.

#include <gtest/gtest.h>

#include <atomic>
#include <thread>
#include <vector>

#include "worker_pool.hpp"

namespace wp = workspace_proximity;

namespace {

struct Job {
  std::vector<std::atomic<int>> runs;  // per part: how often it ran
  std::vector<std::thread::id> thread;  // per part: the thread that ran it last
  std::atomic<int> running{0};
  explicit Job(int parts) : runs(static_cast<std::size_t>(parts)), thread(static_cast<std::size_t>(parts)) {}
  static void task(void* context, int part) {
    Job& job = *static_cast<Job*>(context);
    ++job.running;
    // A little work, so that parts overlap in time when they run on different threads.
    volatile double x = 0.0;
    for (int i = 0; i < 20000; ++i) x = x + 1e-9 * i;
    job.thread[static_cast<std::size_t>(part)] = std::this_thread::get_id();
    ++job.runs[static_cast<std::size_t>(part)];
    --job.running;
  }
};

}  // namespace

TEST(WorkerPool, EveryPartOfEveryJobRunsOnceAndPartZeroOnTheCaller) {
  wp::WorkerPool pool(3);
  EXPECT_EQ(pool.workers(), 3);
  for (int round = 0; round < 500; ++round) {
    const int parts = 1 + round % 4;
    Job job(parts);
    pool.run(parts, &Job::task, &job);
    // run() returned: nothing is still running, and each part ran exactly once.
    ASSERT_EQ(job.running.load(), 0);
    for (int p = 0; p < parts; ++p) ASSERT_EQ(job.runs[static_cast<std::size_t>(p)].load(), 1) << round;
    ASSERT_EQ(job.thread[0], std::this_thread::get_id());
    for (int p = 1; p < parts; ++p) ASSERT_NE(job.thread[static_cast<std::size_t>(p)], std::this_thread::get_id());
  }
}

TEST(WorkerPool, PartsBeyondTheWorkersAreNotRunAndNoWorkersMeansTheCallerAlone) {
  wp::WorkerPool none(0);
  Job alone(3);
  none.run(3, &Job::task, &alone);  // at most workers() + 1 = 1 part
  EXPECT_EQ(alone.runs[0].load(), 1);
  EXPECT_EQ(alone.runs[1].load(), 0);
  EXPECT_EQ(alone.thread[0], std::this_thread::get_id());
  wp::WorkerPool one(1);
  Job two(3);
  one.run(3, &Job::task, &two);
  EXPECT_EQ(two.runs[0].load(), 1);
  EXPECT_EQ(two.runs[1].load(), 1);
  EXPECT_EQ(two.runs[2].load(), 0);
  EXPECT_THROW(wp::WorkerPool bad(-1), std::invalid_argument);
}

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
