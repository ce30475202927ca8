// IoWorker: one background thread that runs file-writing tasks in order, so output stays off the
// simulation's critical path (the runner copies a frame to host memory and hands the write over).
#pragma once

#include <condition_variable>
#include <cstddef>
#include <deque>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>

namespace romp::io {

class IoWorker {
 public:
  // `capacity` tasks may wait (besides the one running) before submit() blocks; at least 1. It bounds
  // the host memory held by frames waiting to be written.
  explicit IoWorker(std::size_t capacity);
  IoWorker(const IoWorker&) = delete;
  IoWorker& operator=(const IoWorker&) = delete;
  // Runs what is queued, then stops. Never throws: a task's pending exception is logged.
  ~IoWorker();

  // Queues `task`, blocking while the queue is full. If an earlier task threw, rethrows that exception
  // instead (once); the tasks queued behind the failed one were dropped, since they may depend on it.
  void submit(std::function<void()> task);
  // Waits until every submitted task has run; rethrows a task's exception as submit() does.
  void drain();

  std::size_t capacity() const { return capacity_; }

 private:
  void run();
  void rethrow_failure(std::unique_lock<std::mutex>& lock);

  const std::size_t capacity_;
  std::mutex mutex_;
  std::condition_variable changed_;  // queue, busy_, failure_ or stopping_ changed
  std::deque<std::function<void()>> queue_;
  bool busy_ = false;
  bool stopping_ = false;
  std::exception_ptr failure_;
  std::thread thread_;  // last, so it starts after everything it uses
};

}  // namespace romp::io
