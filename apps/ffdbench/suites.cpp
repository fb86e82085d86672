#include "bench.h"

namespace ffd::bench {

const std::vector<Suite>& suites() {
  static const std::vector<Suite> all = {
      {"ffd", "lattice FFD throughput against the straightforward triple sum", bench_ffd},
  };
  return all;
}

}  // namespace ffd::bench
