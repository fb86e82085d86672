// Wall-clock stopwatch in milliseconds, for stats and benchmarks.
#pragma once

#include <chrono>

namespace ffd {

/// Starts on construction; ms() reads the elapsed time without stopping it.
class Stopwatch {
public:
  Stopwatch() : start_(std::chrono::steady_clock::now()) {}
  void restart() { start_ = std::chrono::steady_clock::now(); }
  double ms() const {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start_)
        .count();
  }

private:
  std::chrono::steady_clock::time_point start_;
};

}  // namespace ffd
