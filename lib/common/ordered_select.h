// append_selected: the indices 0..n-1 that satisfy a predicate, found in parallel and
// appended in increasing order; ThreadParts, the per-thread lists it and the lattices'
// one-pass scans join in that order.
#pragma once

#include <omp.h>

#include <cstdint>
#include <vector>

namespace ffd {

/// The lists of indices that the threads of a schedule(static) loop keep, one per thread,
/// joined in thread order: the order of the ranges they scanned, so the same list whatever
/// the thread count.
class ThreadParts {
public:
  /// This thread's list, with room for its share of `n` indices (pages nobody writes are
  /// never touched: no reallocation copies when nearly every index is kept). Every thread
  /// of the enclosing parallel region calls it, before the loop.
  std::vector<std::uint32_t>& mine(std::int64_t n) {
#pragma omp single
    parts_.resize(static_cast<std::size_t>(omp_get_num_threads()));
    std::vector<std::uint32_t>& part = parts_[static_cast<std::size_t>(omp_get_thread_num())];
    part.reserve(static_cast<std::size_t>(n / omp_get_num_threads() + 1));
    return part;
  }
  /// Appends the lists to `out`, after the parallel region. The first is moved when `out`
  /// is empty (one thread: no copy).
  void append_to(std::vector<std::uint32_t>& out) {
    std::size_t first = 0;
    if (out.empty() && !parts_.empty()) out = std::move(parts_[first++]);
    for (std::size_t p = first; p < parts_.size(); ++p) out.insert(out.end(), parts_[p].begin(), parts_[p].end());
  }

private:
  std::vector<std::vector<std::uint32_t>> parts_;
};

/// Appends to `out` every i in [0, n) with keep(i), in increasing order. Each thread scans
/// one contiguous range (schedule static) and its finds are appended in range order, so
/// the list is the same whatever the thread count.
template <class Keep>
void append_selected(std::int64_t n, Keep keep, std::vector<std::uint32_t>& out) {
  ThreadParts parts;
#pragma omp parallel
  {
    std::vector<std::uint32_t>& mine = parts.mine(n);
    // A private copy: the shared `keep` is reached through a pointer the appends might
    // alias, so its captures would be reloaded on every index.
    Keep my_keep = keep;
#pragma omp for schedule(static)
    for (std::int64_t i = 0; i < n; ++i)
      if (my_keep(i)) mine.push_back(static_cast<std::uint32_t>(i));
  }
  parts.append_to(out);
}

}  // namespace ffd
