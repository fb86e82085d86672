#include "bench.h"

namespace ffd::bench {

const std::vector<Suite>& suites() {
  static const std::vector<Suite> all = {
      {"ffd", "lattice FFD throughput against the straightforward triple sum", bench_ffd},
      {"remesh", "adaptive remeshing: error against the true surface, speed, memory", bench_remesh},
      {"bcm", "boundary-constraint modeling setup and per-frame cost against CGAL's fair", bench_bcm},
  };
  return all;
}

}  // namespace ffd::bench
