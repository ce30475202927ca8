// EventTimeline on the test backend: each interval gets the time between its marks, summed over runs;
// reading the totals forgets nothing queued after it; a timeline past kCollectEvery marks reads them and
// keeps counting; close before open is an error; a moved timeline keeps its marks.
#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include "kernels/core/error.h"
#include "kernels/core/event_timeline.h"
#include "tests/support/test_exec.h"

namespace romp {
namespace {

// On CUDA nothing is queued between the marks, so only the CPU sees the host's sleeps.
bool host_clock() { return !test::exec().is_cuda(); }

void pause_ms(int milliseconds) { std::this_thread::sleep_for(std::chrono::milliseconds(milliseconds)); }

TEST(EventTimeline, IntervalsSumTheTimeBetweenTheirMarks) {
  EventTimeline timeline(test::exec());
  for (int run = 0; run < 2; ++run) {
    timeline.open();
    pause_ms(3);
    timeline.close(0);
    pause_ms(1);
    timeline.close(1);
  }
  const std::vector<double> seconds = timeline.seconds();
  ASSERT_EQ(seconds.size(), 2u);
  EXPECT_GE(seconds[0], 0.0);
  EXPECT_GE(seconds[1], 0.0);
  if (host_clock()) {
    EXPECT_GE(seconds[0], 6e-3);
    EXPECT_GE(seconds[1], 2e-3);
  }
  // A second read adds nothing; later marks add to the same totals.
  EXPECT_EQ(timeline.seconds(), seconds);
  timeline.open();
  pause_ms(2);
  timeline.close(1);
  if (host_clock()) EXPECT_GE(timeline.seconds()[1], seconds[1] + 2e-3);
  EXPECT_EQ(timeline.seconds()[0], seconds[0]);
}

// Past kCollectEvery marks an open() reads them: what was marked before and after that read both count.
TEST(EventTimeline, ReadsItsMarksWhenTheyPileUpAndKeepsCounting) {
  EventTimeline timeline(test::exec());
  const int runs = int(EventTimeline::kCollectEvery);  // 2 marks a run: past the limit halfway
  for (int run = 0; run < runs; ++run) {
    timeline.open();
    if (run == 0 || run == runs - 1) pause_ms(2);  // before and after the read halfway
    timeline.close(0);
  }
  const double total = timeline.seconds()[0];
  EXPECT_GE(total, 0.0);
  if (host_clock()) EXPECT_GE(total, 4e-3);
  EXPECT_LT(total, 10.0);
}

TEST(EventTimeline, CloseBeforeOpenIsAnError) {
  EventTimeline timeline(test::exec());
  EXPECT_THROW(timeline.close(0), Error);
}

TEST(EventTimeline, AMovedTimelineKeepsItsMarks) {
  EventTimeline first(test::exec());
  first.open();
  pause_ms(2);
  first.close(0);
  EventTimeline moved(std::move(first));
  moved.close(1);
  const std::vector<double> seconds = moved.seconds();
  ASSERT_EQ(seconds.size(), 2u);
  if (host_clock()) EXPECT_GE(seconds[0], 2e-3);
}

}  // namespace
}  // namespace romp
