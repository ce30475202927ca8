// EventTimeline: cudaEventRecord now, cudaEventElapsedTime later; std::chrono::steady_clock on the CPU.
#include "kernels/core/event_timeline.h"

#include <utility>

#include "kernels/core/error.h"

#if defined(ROMP_WITH_CUDA)
#include "kernels/core/cuda_check.h"
#endif

namespace romp {

EventTimeline::EventTimeline(const Exec& exec) : exec_(exec) {
#if !defined(ROMP_WITH_CUDA)
  ROMP_CHECK(!exec.is_cuda(), "EventTimeline: the CUDA backend is not compiled into this build");
#endif
}

EventTimeline::~EventTimeline() { release(); }

EventTimeline::EventTimeline(EventTimeline&& other) noexcept
    : exec_(other.exec_),
      marks_(std::move(other.marks_)),
      events_(std::move(other.events_)),
      seconds_(std::move(other.seconds_)) {
  other.events_.clear();
}

EventTimeline& EventTimeline::operator=(EventTimeline&& other) noexcept {
  if (this != &other) {
    release();
    exec_ = other.exec_;
    marks_ = std::move(other.marks_);
    events_ = std::move(other.events_);
    seconds_ = std::move(other.seconds_);
    other.events_.clear();
  }
  return *this;
}

void EventTimeline::release() {
#if defined(ROMP_WITH_CUDA)
  for (CUevent_st* event : events_) ROMP_CUDA_CHECK_NOTHROW(cudaEventDestroy(event));
#endif
  events_.clear();
}

void EventTimeline::open() {
  if (marks_.size() >= kCollectEvery) collect();
  record(kOpens);
}

void EventTimeline::close(std::size_t interval) {
  ROMP_CHECK(!marks_.empty(), "EventTimeline::close before open");
  record(std::ptrdiff_t(interval));
}

void EventTimeline::record(std::ptrdiff_t interval) {
  marks_.push_back(Mark{interval, {}});
#if defined(ROMP_WITH_CUDA)
  if (exec_.is_cuda()) {
    if (events_.size() < marks_.size()) {
      CUevent_st* event = nullptr;
      ROMP_CUDA_CHECK(cudaEventCreate(&event));
      events_.push_back(event);
    }
    ROMP_CUDA_CHECK(cudaEventRecord(events_[marks_.size() - 1], exec_.stream));
    return;
  }
#endif
  marks_.back().time = std::chrono::steady_clock::now();
}

void EventTimeline::collect() {
  if (marks_.empty()) return;
#if defined(ROMP_WITH_CUDA)
  if (exec_.is_cuda()) ROMP_CUDA_CHECK(cudaEventSynchronize(events_[marks_.size() - 1]));
#endif
  for (std::size_t i = 1; i < marks_.size(); ++i) {
    if (marks_[i].interval == kOpens) continue;
    double elapsed = 0.0;
#if defined(ROMP_WITH_CUDA)
    if (exec_.is_cuda()) {
      float milliseconds = 0.0f;
      ROMP_CUDA_CHECK(cudaEventElapsedTime(&milliseconds, events_[i - 1], events_[i]));
      elapsed = double(milliseconds) * 1e-3;
    }
#endif
    if (!exec_.is_cuda()) elapsed = std::chrono::duration<double>(marks_[i].time - marks_[i - 1].time).count();
    const std::size_t interval = std::size_t(marks_[i].interval);
    if (seconds_.size() <= interval) seconds_.resize(interval + 1, 0.0);
    seconds_[interval] += elapsed;
  }
  // The last mark, read now, starts whatever interval comes next.
  const std::size_t last = marks_.size() - 1;
  if (exec_.is_cuda()) std::swap(events_[0], events_[last]);
  marks_.assign(1, Mark{kOpens, marks_[last].time});
}

const std::vector<double>& EventTimeline::seconds() {
  collect();
  return seconds_;
}

}  // namespace romp
