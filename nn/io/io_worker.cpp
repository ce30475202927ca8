// IoWorker: a bounded queue, one thread, and exceptions carried back to the submitting thread.
#include "nn/io/io_worker.h"

#include <spdlog/spdlog.h>

#include "kernels/core/error.h"

namespace romp::io {

IoWorker::IoWorker(std::size_t capacity) : capacity_(capacity) {
  if (capacity_ == 0) throw Error("IoWorker: the queue capacity must be at least 1");
  thread_ = std::thread([this] { run(); });
}

IoWorker::~IoWorker() {
  std::unique_lock<std::mutex> lock(mutex_);
  changed_.wait(lock, [this] { return queue_.empty() && !busy_; });
  stopping_ = true;
  const std::exception_ptr failure = failure_;
  lock.unlock();
  changed_.notify_all();
  thread_.join();
  if (failure) {
    try {
      std::rethrow_exception(failure);
    } catch (const std::exception& error) {
      spdlog::error("I/O worker: a write failed and was not reported before shutdown: {}", error.what());
    } catch (...) {
      spdlog::error("I/O worker: a write failed with an unknown exception and was not reported before shutdown");
    }
  }
}

void IoWorker::rethrow_failure(std::unique_lock<std::mutex>& lock) {
  if (!failure_) return;
  const std::exception_ptr failure = failure_;
  failure_ = nullptr;
  lock.unlock();
  std::rethrow_exception(failure);
}

void IoWorker::submit(std::function<void()> task) {
  std::unique_lock<std::mutex> lock(mutex_);
  rethrow_failure(lock);
  changed_.wait(lock, [this] { return queue_.size() < capacity_ || failure_; });
  rethrow_failure(lock);
  queue_.push_back(std::move(task));
  lock.unlock();
  changed_.notify_all();
}

void IoWorker::drain() {
  std::unique_lock<std::mutex> lock(mutex_);
  changed_.wait(lock, [this] { return queue_.empty() && !busy_; });
  rethrow_failure(lock);
}

void IoWorker::run() {
  std::unique_lock<std::mutex> lock(mutex_);
  for (;;) {
    changed_.wait(lock, [this] { return !queue_.empty() || stopping_; });
    if (queue_.empty()) return;
    std::function<void()> task = std::move(queue_.front());
    queue_.pop_front();
    busy_ = true;
    lock.unlock();
    changed_.notify_all();  // a slot is free
    std::exception_ptr failure;
    try {
      task();
    } catch (...) {
      failure = std::current_exception();
    }
    task = nullptr;  // release what the task captured (a frame's copy) before taking the next
    lock.lock();
    busy_ = false;
    if (failure) {
      failure_ = failure;
      queue_.clear();
    }
    changed_.notify_all();
  }
}

}  // namespace romp::io
