// ThreadChoice: the thread count of a repeated short parallel task, chosen by measuring it.
//
// A BCM frame takes a fraction of a millisecond, and its team meets at a few barriers: on
// a busy machine one descheduled thread stalls the whole team for a scheduler slice, and
// the team's frame costs many times one thread's. So a sequence of frames times both
// choices (one thread, the whole team) and runs each frame with the one whose recent frames
// were faster, trying the other again in case the load changed: after kExplore frames, then
// twice as many each time the try confirms the choice (a stalled try costs a scheduler
// slice), and again after kExplore once the choice changes.
// The task must give the same result whatever its thread count (bcm_pose does).
#pragma once

#include <algorithm>
#include <cstddef>

namespace ffd {

class ThreadChoice {
public:
  static constexpr std::size_t kExplore = 16;
  static constexpr std::size_t kMaxInterval = 4096;

  /// `team`: the whole team's size (omp_get_max_threads()).
  explicit ThreadChoice(int team) : team_(team) {}
  /// The thread count for the next run of the task.
  int next() const {
    if (team_ <= 1) return 1;
    if (ms_[0] < 0) return 1;  // measure each once first
    if (ms_[1] < 0) return team_;
    const int pick = runs_ == explore_at_ ? 1 - better() : better();
    return pick == 0 ? 1 : team_;
  }
  /// Records that a run with `threads` threads took `ms`.
  void record(int threads, double ms) {
    const int before = better();
    double& mean = ms_[threads == 1 ? 0 : 1];
    // A faster run counts at once (the first runs pay for starting the team); slower ones
    // weigh in a quarter each, so that one stall moves the choice but noise does not.
    mean = mean < 0 || ms < mean ? ms : 0.75 * mean + 0.25 * ms;
    ++(threads == 1 ? single_runs_ : team_runs_);
    if (runs_ == explore_at_ || better() != before) {
      interval_ = better() == before ? std::min(2 * interval_, kMaxInterval) : kExplore;
      explore_at_ = runs_ + interval_;
    }
    ++runs_;
  }
  std::size_t single_runs() const { return single_runs_; }
  std::size_t team_runs() const { return team_runs_; }

private:
  int better() const { return ms_[1] >= 0 && ms_[1] < ms_[0] ? 1 : 0; }

  int team_;
  double ms_[2] = {-1, -1};  // recent mean ms: one thread, the team; < 0: not measured
  std::size_t runs_ = 0, single_runs_ = 0, team_runs_ = 0;
  std::size_t interval_ = kExplore, explore_at_ = kExplore;
};

}  // namespace ffd
