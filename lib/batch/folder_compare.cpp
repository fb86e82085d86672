#include "batch/folder_compare.h"

#include <omp.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <set>

#include "batch/batch_items.h"
#include "common/errors.h"
#include "common/timer.h"
#include "mesh/mesh_io.h"

namespace ffd {
namespace fs = std::filesystem;

std::string difference_line(const MeshDifference& d, double tolerance) {
  if (!d.comparable) return d.reason;
  if (d.metric == "vertex" && !d.same_connectivity) return d.reason;
  char line[160];
  std::snprintf(line, sizeof line, "%s distance %.6g > tolerance %g", d.metric.c_str(), d.max, tolerance);
  return line;
}

namespace {

// The paths of both folders, each once, sorted; with which side has it.
std::vector<PairResult> pair_paths(const std::string& a, const std::string& b, bool recursive) {
  const std::vector<std::string> in_a = mesh_files_under(a, recursive), in_b = mesh_files_under(b, recursive);
  std::set<std::string> all(in_a.begin(), in_a.end());
  all.insert(in_b.begin(), in_b.end());
  std::vector<PairResult> out;
  for (const std::string& path : all) {
    PairResult r;
    r.path = path;
    if (!std::binary_search(in_b.begin(), in_b.end(), path)) r.status = PairResult::Status::OnlyInA;
    if (!std::binary_search(in_a.begin(), in_a.end(), path)) r.status = PairResult::Status::OnlyInB;
    out.push_back(r);
  }
  return out;
}

// Reads and compares one pair; any error is the pair's.
void compare_pair(const std::string& a, const std::string& b, const FolderCompareOptions& options, PairResult& r) {
  Stopwatch clock;
  try {
    const auto [ma, mb] = read_mesh_pair((fs::path(a) / r.path).string(), (fs::path(b) / r.path).string());
    r.difference = compare_meshes(ma, mb, options.compare);
    const bool same = within_tolerance(r.difference, options.compare.tolerance);
    r.status = same ? PairResult::Status::Same : PairResult::Status::Different;
    if (!same) {
      r.message = difference_line(r.difference, options.compare.tolerance);
      if (options.on_different) options.on_different(r, mb);
    }
  } catch (const std::exception& e) {
    r.status = PairResult::Status::Error;
    r.message = e.what();
  }
  r.difference.distances = {};
  r.difference.distances.shrink_to_fit();
  r.ms = clock.ms();
}

// The pairs by the bytes of their two files, largest first (ties by path): handed out in
// that order, the long pairs start first and the short ones fill in after, instead of a
// long pair late in path order running alone at the end.
std::vector<std::size_t> largest_first(const std::string& a, const std::string& b, const std::vector<PairResult>& pairs) {
  std::vector<std::uintmax_t> bytes(pairs.size(), 0);
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    std::error_code ec;
    for (const std::string& side : {a, b}) {
      const std::uintmax_t size = fs::file_size(fs::path(side) / pairs[i].path, ec);
      if (!ec) bytes[i] += size;
    }
  }
  std::vector<std::size_t> order(pairs.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(), [&](std::size_t x, std::size_t y) { return bytes[x] > bytes[y]; });
  return order;
}

void count(FolderComparison& c) {
  c.worst = c.pairs.size();
  for (std::size_t i = 0; i < c.pairs.size(); ++i) {
    const PairResult& r = c.pairs[i];
    switch (r.status) {
      case PairResult::Status::Same: ++c.same; break;
      case PairResult::Status::Different: ++c.different; break;
      case PairResult::Status::OnlyInA: ++c.only_in_a; break;
      case PairResult::Status::OnlyInB: ++c.only_in_b; break;
      case PairResult::Status::Error: ++c.errors; break;
    }
    const bool measured = r.status == PairResult::Status::Same || r.status == PairResult::Status::Different;
    if (measured && r.difference.comparable &&
        (c.worst == c.pairs.size() || r.difference.max > c.pairs[c.worst].difference.max))
      c.worst = i;
  }
}

}  // namespace

FolderComparison compare_folders(const std::string& a, const std::string& b, const FolderCompareOptions& options) {
  FolderComparison c;
  c.pairs = pair_paths(a, b, options.recursive);
  const int jobs = options.jobs ? static_cast<int>(options.jobs) : omp_get_max_threads();
  const std::vector<std::size_t> order = largest_first(a, b, c.pairs);
  const auto n = static_cast<long long>(order.size());
  // One pair per thread, and a pair's own passes on every core too (nested): when one
  // long pair is left, it does not run alone on one core. The results do not depend on
  // the threads.
  const int levels = omp_get_max_active_levels();
  omp_set_max_active_levels(2);
#pragma omp parallel for schedule(dynamic, 1) num_threads(jobs)
  for (long long i = 0; i < n; ++i) {
    PairResult& r = c.pairs[order[static_cast<std::size_t>(i)]];
    if (r.status == PairResult::Status::Same) compare_pair(a, b, options, r);
  }
  omp_set_max_active_levels(levels);
  count(c);
  return c;
}

}  // namespace ffd
