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
  // The first try and five more of kTrialRuns frames each (after 16, 32, ... 256 frames).
  EXPECT_LE(single, 6 * ThreadChoice::kTrialRuns);
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

// The 33k head's frames (thread_choice.h): the team's first frame after frames on one
// thread pays for waking its thread and warming its cache, and so does one thread's first
// frame after the team's. A choice made on such frames kept one thread for 995 of 1,001
// frames, each taking the team's frame and a third again.
TEST(ThreadChoice, ACountThatMustWakeUpFirstIsJudgedOnItsLaterFrames) {
  ThreadChoice choice(2);
  int last = 0;
  const auto cost = [&](int t) {
    const double ms = t == 1 ? (last == 2 ? 0.8 : 0.5) : (last == 1 ? 1.5 : 0.38);
    last = t;
    return ms;
  };
  EXPECT_LE(run(choice, 1000, cost), 6 * ThreadChoice::kTrialRuns);
  last = 0;
  ThreadChoice slower_team(2);  // and the other way round: the team's later frames lose
  const auto team_loses = [&](int t) {
    const double ms = t == 1 ? (last == 2 ? 0.8 : 0.38) : (last == 1 ? 1.5 : 0.5);
    last = t;
    return ms;
  };
  EXPECT_GE(run(slower_team, 1000, team_loses), 1000 - 6 * ThreadChoice::kTrialRuns);
}

}  // namespace
}  // namespace ffd
