// ThreadChoice: the thread count of a repeated short parallel task, chosen by measuring it.
//
// A BCM frame takes a fraction of a millisecond, and its team meets at a few barriers: on
// a busy machine one descheduled thread stalls the whole team for a scheduler slice, and
// the team's frame costs many times one thread's. So a sequence of frames times both
// choices (one thread, the whole team) and runs each frame with the one whose recent frames
// were faster, trying the other again in case the load changed: after kExplore frames, then
// twice as many each time the try confirms the choice (a stalled try costs a scheduler
// slice), and again after kExplore once the choice changes.
// A try is kTrialRuns frames, not one: the first frame of a count that has not run for a
// while pays for waking its threads and for data that is in the other core's cache (the
// team's first frame after 15 frames on one thread took 1.2-1.8 ms on the 33k head,
// against 0.38 ms from its third frame on, and one thread's frame 0.5 ms), so a single
// frame's try kept the slower count. The same holds for the first frame back after a try,
// so such a first frame counts only if it is faster, or a stall: more than kStall times
// the other count's. A try ends at a stall.
// The task must give the same result whatever its thread count (bcm_pose does).
#pragma once

#include <algorithm>
#include <cstddef>

namespace ffd {

class ThreadChoice {
public:
  static constexpr std::size_t kExplore = 16;
  static constexpr std::size_t kMaxInterval = 4096;
  static constexpr std::size_t kTrialRuns = 3;
  static constexpr double kStall = 8;

  /// `team`: the whole team's size (omp_get_max_threads()).
  explicit ThreadChoice(int team) : team_(team) {}
  /// The thread count for the next run of the task.
  int next() const {
    if (team_ <= 1) return 1;
    return (trial_left_ > 0 ? trial_ : better()) == 0 ? 1 : team_;
  }
  /// Records that a run with `threads` threads took `ms`.
  void record(int threads, double ms) {
    const int option = threads == 1 ? 0 : 1;
    const bool warm_up = option != last_, stall = ms_[1 - option] >= 0 && ms > kStall * ms_[1 - option];
    double& mean = ms_[option];
    // A faster run counts at once (the first runs pay for starting the team); slower ones
    // weigh in a quarter each, so that one stall moves the choice but noise does not. A
    // slower first run after the other count's runs is a warm-up, and does not count
    // unless it is a stall.
    if (mean < 0 || ms < mean) {
      mean = ms;
    } else if (!warm_up || stall) {
      mean = 0.75 * mean + 0.25 * ms;
    }
    last_ = option;
    ++(option == 0 ? single_runs_ : team_runs_);
    ++runs_;
    if (team_ <= 1) return;
    if (trial_left_ > 0) {
      trial_run(option, stall);
    } else if (better() != chosen_) {  // the chosen count stalled
      choose(kExplore);
    } else if (runs_ >= explore_at_) {
      trial_ = 1 - chosen_;
      trial_left_ = kTrialRuns;
    }
  }
  std::size_t single_runs() const { return single_runs_; }
  std::size_t team_runs() const { return team_runs_; }

private:
  int better() const { return ms_[1] >= 0 && ms_[1] < ms_[0] ? 1 : 0; }
  void trial_run(int option, bool stall) {
    trial_left_ = stall ? 0 : trial_left_ - 1;
    if (trial_left_ > 0) return;
    if (ms_[1 - option] < 0) {  // the first try of each count: one thread, then the team
      trial_ = 1 - option;
      trial_left_ = kTrialRuns;
    } else {
      choose(chosen_ < 0 || better() != chosen_ ? kExplore : std::min(2 * interval_, kMaxInterval));
    }
  }
  void choose(std::size_t interval) {
    chosen_ = better();
    interval_ = interval;
    explore_at_ = runs_ + interval_;
  }

  int team_;
  double ms_[2] = {-1, -1};  // recent mean ms: one thread, the team; < 0: not measured
  std::size_t runs_ = 0, single_runs_ = 0, team_runs_ = 0;
  int trial_ = 0, chosen_ = -1, last_ = -1;  // 0: one thread, 1: the team; < 0: none yet
  std::size_t trial_left_ = kTrialRuns;
  std::size_t interval_ = kExplore, explore_at_ = 0;
};

}  // namespace ffd
