// ThreadChoice (lib/common/thread_choice.h): the thread count of BCM frames, chosen by
// measuring both counts, on made-up timings.
#include <gtest/gtest.h>

#include "common/thread_choice.h"

namespace ffd {
namespace {

// Runs `frames` frames whose cost is `ms(threads)`; returns how many ran on one thread.
template <class Cost>
std::size_t run(ThreadChoice& choice, std::size_t frames, Cost ms) {
  const std::size_t before = choice.single_runs();
  for (std::size_t f = 0; f < frames; ++f) {
    const int threads = choice.next();
    choice.record(threads, ms(threads));
  }
  return choice.single_runs() - before;
}

TEST(ThreadChoice, OneThreadAlwaysWhenThereIsNoTeam) {
  ThreadChoice choice(1);
  EXPECT_EQ(run(choice, 100, [](int) { return 1.0; }), 100u);
}

TEST(ThreadChoice, TheFasterCountRunsAlmostEveryFrame) {
  ThreadChoice quiet(2);  // the team halves a frame
  const std::size_t single = run(quiet, 1000, [](int t) { return t == 1 ? 0.4 : 0.2; });
  EXPECT_LE(single, 12u);
  ThreadChoice busy(2);  // the team stalls for a scheduler slice
  EXPECT_GE(run(busy, 1000, [](int t) { return t == 1 ? 0.4 : 30.0; }), 985u);
}

TEST(ThreadChoice, TheChoiceFollowsTheLoad) {
  ThreadChoice choice(2);
  bool busy = true;
  const auto cost = [&](int t) { return t == 1 ? 0.4 : busy ? 30.0 : 0.2; };
  EXPECT_GE(run(choice, 500, cost), 490u);
  busy = false;  // the machine frees up: the team wins back within the exploring interval
  run(choice, ThreadChoice::kMaxInterval + 1, cost);
  EXPECT_LE(run(choice, 500, cost), 10u);
  busy = true;  // and loses at its first stall; the tries after it back off (16, 32, ...)
  EXPECT_GE(run(choice, 500, cost), 490u);
}

}  // namespace
}  // namespace ffd
