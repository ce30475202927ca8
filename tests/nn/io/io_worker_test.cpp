// IoWorker: tasks run in order on one thread, submit blocks on a full queue, and a task's exception
// comes back to the submitting thread.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <future>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "kernels/core/error.h"
#include "nn/io/io_worker.h"

namespace romp::io {
namespace {

TEST(IoWorker, RunsTasksInOrderOffTheCallingThread) {
  std::vector<int> order;
  std::thread::id worker_thread;
  {
    IoWorker worker(2);
    for (int i = 0; i < 100; ++i) {
      worker.submit([&order, &worker_thread, i] {
        order.push_back(i);
        worker_thread = std::this_thread::get_id();
      });
    }
    worker.drain();
    EXPECT_EQ(order.size(), 100u);
  }
  for (int i = 0; i < 100; ++i) EXPECT_EQ(order[std::size_t(i)], i);
  EXPECT_NE(worker_thread, std::this_thread::get_id());
}

TEST(IoWorker, SubmitBlocksWhileTheQueueIsFull) {
  IoWorker worker(1);
  std::promise<void> release;
  std::shared_future<void> released = release.get_future().share();
  std::promise<void> started;
  worker.submit([&started, released] {
    started.set_value();
    released.wait();
  });
  started.get_future().wait();  // the first task runs, the queue is empty
  worker.submit([] {});         // fills the queue
  std::atomic<bool> third_accepted{false};
  std::thread submitter([&] {
    worker.submit([] {});
    third_accepted = true;
  });
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  EXPECT_FALSE(third_accepted.load());
  release.set_value();
  submitter.join();
  EXPECT_TRUE(third_accepted.load());
  worker.drain();
}

TEST(IoWorker, ATaskExceptionIsRethrownByTheNextSubmit) {
  IoWorker worker(4);
  worker.submit([] { throw Error("disk full"); });
  // Submits succeed until the worker has run the failing task; the next one reports it.
  std::string message;
  for (int attempt = 0; attempt < 10000 && message.empty(); ++attempt) {
    try {
      worker.submit([] {});
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    } catch (const Error& error) {
      message = error.what();
    }
  }
  EXPECT_EQ(message, "disk full");
  EXPECT_NO_THROW(worker.drain());  // reported once
}

TEST(IoWorker, ATaskExceptionIsRethrownByDrainAndLaterTasksAreDropped) {
  IoWorker worker(4);
  std::promise<void> release;
  std::shared_future<void> released = release.get_future().share();
  bool later_ran = false;
  worker.submit([released] {
    released.wait();
    throw std::runtime_error("cannot write frame 3");
  });
  worker.submit([&later_ran] { later_ran = true; });
  release.set_value();
  EXPECT_THROW(
      {
        try {
          worker.drain();
        } catch (const std::runtime_error& error) {
          EXPECT_STREQ(error.what(), "cannot write frame 3");
          throw;
        }
      },
      std::runtime_error);
  EXPECT_FALSE(later_ran);
  // The worker goes on with new tasks.
  bool next_ran = false;
  worker.submit([&next_ran] { next_ran = true; });
  worker.drain();
  EXPECT_TRUE(next_ran);
}

TEST(IoWorker, DestructorRunsQueuedTasksAndDoesNotThrow) {
  int ran = 0;
  {
    IoWorker worker(8);
    for (int i = 0; i < 5; ++i) worker.submit([&ran] { ++ran; });
  }
  EXPECT_EQ(ran, 5);
  {
    IoWorker worker(2);
    worker.submit([] { throw Error("never reported"); });
  }  // logged, not thrown
  EXPECT_THROW(IoWorker(0), Error);
}

}  // namespace
}  // namespace romp::io
