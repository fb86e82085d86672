// append_selected: the indices 0..n-1 that satisfy a predicate, found in parallel and
// appended in increasing order.
#pragma once

#include <omp.h>

#include <cstdint>
#include <vector>

namespace ffd {

/// Appends the threads' parts to `out` in thread order: with schedule(static), the order
/// of the ranges they scanned. The first part is moved when `out` is empty (one thread: no
/// copy).
inline void append_parts(std::vector<std::vector<std::uint32_t>>& parts, std::vector<std::uint32_t>& out) {
  std::size_t first = 0;
  if (out.empty() && !parts.empty()) out = std::move(parts[first++]);
  for (std::size_t p = first; p < parts.size(); ++p) out.insert(out.end(), parts[p].begin(), parts[p].end());
}

/// Appends to `out` every i in [0, n) with keep(i), in increasing order. Each thread scans
/// one contiguous range (schedule static) and its finds are appended in range order, so
/// the list is the same whatever the thread count.
template <class Keep>
void append_selected(std::int64_t n, Keep keep, std::vector<std::uint32_t>& out) {
  std::vector<std::vector<std::uint32_t>> parts;
#pragma omp parallel
  {
#pragma omp single
    parts.resize(static_cast<std::size_t>(omp_get_num_threads()));
    std::vector<std::uint32_t>& mine = parts[static_cast<std::size_t>(omp_get_thread_num())];
    // Room for the whole range at once (pages nobody writes are never touched): no
    // reallocation copies when nearly every index is kept.
    mine.reserve(static_cast<std::size_t>(n / omp_get_num_threads() + 1));
    // A private copy: the shared `keep` is reached through a pointer the appends might
    // alias, so its captures would be reloaded on every index.
    Keep my_keep = keep;
#pragma omp for schedule(static)
    for (std::int64_t i = 0; i < n; ++i)
      if (my_keep(i)) mine.push_back(static_cast<std::uint32_t>(i));
  }
  append_parts(parts, out);
}

}  // namespace ffd
