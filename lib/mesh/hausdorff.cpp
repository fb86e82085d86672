#include "mesh/hausdorff.h"

#include <omp.h>

#include <algorithm>
#include <array>
#include <cmath>

namespace ffd {

namespace {

// Vertices and triangles are handed out in blocks of this many, whatever the thread
// count: a search's hint is the previous vertex's answer within its block, so the blocks
// must not depend on the threads for the results not to.
constexpr std::size_t kBlock = 256;
// Splitting depth past which a sub-triangle's bounds are taken as they are (its diameter
// is then 2^-32 of its triangle's; an error bound of 1e-9 of the meshes' size is reached
// long before).
constexpr int kMaxDepth = 32;

int thread_count(const HausdorffOptions& options) {
  return options.threads > 0 ? options.threads : omp_get_max_threads();
}

std::size_t blocks_of(std::size_t n) { return (n + kBlock - 1) / kBlock; }

// Every point's (every vertex a triangle uses) distance to `to` and its closest triangle there.
struct VertexPass {
  std::vector<double> distance;
  std::vector<std::uint32_t> closest;
  double max = 0;
  std::size_t points = 0;
};

VertexPass vertex_pass(const SurfaceIndex& from, const SurfaceIndex& to, bool matched, int threads) {
  const std::size_t n = from.num_points();
  VertexPass out;
  out.distance.assign(n, 0);
  out.closest.assign(n, SurfaceIndex::kNone);
  const auto blocks = static_cast<long long>(blocks_of(n));
#pragma omp parallel for schedule(dynamic, 16) num_threads(threads)
  for (long long b = 0; b < blocks; ++b) {
    std::uint32_t hint = SurfaceIndex::kNone;
    const std::size_t end = std::min(n, (static_cast<std::size_t>(b) + 1) * kBlock);
    for (std::size_t i = static_cast<std::size_t>(b) * kBlock; i < end; ++i) {
      const auto point = static_cast<std::uint32_t>(i);
      if (matched) {
        const std::uint32_t image = to.point_of_vertex(from.mesh_vertex(point));
        if (image != SurfaceIndex::kNone) hint = to.triangle_of_point(image);
      }
      const SurfaceIndex::Closest c = to.closest(from.point(point), hint);
      out.distance[i] = std::sqrt(c.squared);
      out.closest[i] = hint = c.triangle;
    }
  }
  for (const double d : out.distance) out.max = std::max(out.max, d);
  out.points = n;
  return out;
}

// The points' distances by mesh vertex (NaN for a vertex no polygon uses).
std::vector<double> by_mesh_vertex(const SurfaceIndex& index, const std::vector<double>& distance) {
  std::vector<double> out(index.num_mesh_vertices(), std::nan(""));
  for (std::uint32_t p = 0; p < distance.size(); ++p) out[index.mesh_vertex(p)] = distance[p];
  return out;
}

// A (sub-)triangle of `from`: its corners with their distances and closest triangles of
// `to`, and the triangle that bounded its parent best.
struct Corner {
  Eigen::Vector3d p;
  double d = 0;
  std::uint32_t closest = SurfaceIndex::kNone;
};
struct Piece {
  std::array<Corner, 3> corner;
  std::uint32_t parent_best = SurfaceIndex::kNone;
  int depth = 0;
};

struct Bounds {
  double lower = 0, upper = 0;
  std::uint32_t best = SurfaceIndex::kNone;  // the triangle of `to` that gives `upper`
};

// l = the corners' largest distance; u = min over the candidates t of the largest
// distance of a corner to t (d(·, t) is convex, so no point of the piece is farther from
// t), or l plus the farthest any point lies from its nearest corner.
Bounds piece_bounds(const Piece& s, const SurfaceIndex& to) {
  Bounds b;
  for (const Corner& c : s.corner) b.lower = std::max(b.lower, c.d);
  const std::array<std::uint32_t, 4> candidates = {s.corner[0].closest, s.corner[1].closest, s.corner[2].closest,
                                                   s.parent_best};
  if (candidates[0] == candidates[1] && candidates[1] == candidates[2]) return {b.lower, b.lower, candidates[0]};
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < candidates.size(); ++i) {
    const std::uint32_t t = candidates[i];
    if (t == SurfaceIndex::kNone || std::find(candidates.begin(), candidates.begin() + i, t) != candidates.begin() + i)
      continue;
    double worst = 0;
    for (const Corner& c : s.corner) worst = std::max(worst, c.closest == t ? c.d * c.d : to.squared_distance(c.p, t));
    if (worst < best) {
      best = worst;
      b.best = t;
    }
  }
  // d(·, to) is 1-Lipschitz: no point is farther than its nearest corner's distance plus
  // its distance to that corner, which is at most the longest edge / sqrt(3).
  double longest = 0;
  for (int i = 0; i < 3; ++i) longest = std::max(longest, (s.corner[i].p - s.corner[(i + 1) % 3].p).squaredNorm());
  b.upper = std::max(b.lower, std::min(std::sqrt(best), b.lower + std::sqrt(longest / 3)));
  return b;
}

// What a piece's bounds are measured against.
struct Limits {
  double reached = 0;    // a distance already reached: pieces below it are dropped
  double tolerance = 0;
  double error = 0;
  bool decide = false;   // split pieces that could hold the first point beyond the tolerance
};

// Whether a piece needs no split: it cannot raise the distance found by more than the
// error, nor (when deciding) hold the first point found beyond the tolerance but within
// half the error of its own bounds (so a distance over tolerance + error / 2 is always
// found), or it is as small as it gets.
bool settled(const Bounds& b, const Piece& s, double known, const Limits& limits) {
  const bool open = limits.decide && known <= limits.tolerance && b.upper > limits.tolerance;
  if (s.depth >= kMaxDepth) return true;
  return open ? b.upper - b.lower <= limits.error / 2 : b.upper <= known + limits.error;
}

Corner midpoint(const Corner& a, const Corner& b, std::uint32_t hint, const SurfaceIndex& to) {
  Corner m;
  m.p = 0.5 * (a.p + b.p);
  const SurfaceIndex::Closest c = to.closest(m.p, hint);
  m.d = std::sqrt(c.squared);
  m.closest = c.triangle;
  return m;
}

struct TriangleResult {
  double lower = 0, upper = 0;
  std::size_t points = 0, splits = 0;
};

// Splits one triangle of `from` until every piece is settled or dropped.
TriangleResult refine(const Piece& root, const SurfaceIndex& to, const Limits& limits) {
  TriangleResult r;
  std::vector<Piece> stack = {root};
  while (!stack.empty()) {
    const Piece s = stack.back();
    stack.pop_back();
    const Bounds b = piece_bounds(s, to);
    r.lower = std::max(r.lower, b.lower);
    const double known = std::max(limits.reached, r.lower);
    if (b.upper <= known) continue;  // holds no farther point
    if (settled(b, s, known, limits)) {
      r.upper = std::max(r.upper, b.upper);
      continue;
    }
    const std::array<Corner, 3>& c = s.corner;
    const Corner m01 = midpoint(c[0], c[1], b.best, to), m12 = midpoint(c[1], c[2], b.best, to),
                 m20 = midpoint(c[2], c[0], b.best, to);
    r.points += 3;
    ++r.splits;
    for (const std::array<Corner, 3>& corners : {std::array<Corner, 3>{c[0], m01, m20}, std::array<Corner, 3>{m01, c[1], m12},
                                                 std::array<Corner, 3>{m20, m12, c[2]}, std::array<Corner, 3>{m12, m20, m01}})
      stack.push_back({corners, b.best, s.depth + 1});
  }
  return r;
}

// Bounds of every triangle of `from`; the largest lower and upper bounds, the points
// measured and the triangles split.
TriangleResult triangle_pass(const SurfaceIndex& from, const SurfaceIndex& to, const VertexPass& vertices,
                             const Limits& limits, bool matched, int threads) {
  const std::size_t n = from.num_triangles();
  const bool same_triangles = matched && n == to.num_triangles();
  const auto blocks = static_cast<long long>(blocks_of(n));
  double lower = limits.reached, upper = limits.reached;
  std::size_t points = 0, splits = 0;
#pragma omp parallel for schedule(dynamic, 16) num_threads(threads) reduction(max : lower, upper) reduction(+ : points, splits)
  for (long long b = 0; b < blocks; ++b) {
    const std::size_t end = std::min(n, (static_cast<std::size_t>(b) + 1) * kBlock);
    for (std::size_t i = static_cast<std::size_t>(b) * kBlock; i < end; ++i) {
      const auto t = static_cast<std::uint32_t>(i);
      Piece root;
      // Matched meshes of as many triangles: the triangle of `to` in t's place among the
      // fanned polygons is likely t's image (a deformed copy), the candidate that bounds it best.
      if (same_triangles) root.parent_best = to.triangle_at_fan_index(from.fan_index(t));
      const std::array<std::uint32_t, 3>& v = from.triangle(t);
      for (int k = 0; k < 3; ++k) root.corner[k] = {from.point(v[k]), vertices.distance[v[k]], vertices.closest[v[k]]};
      const TriangleResult r = refine(root, to, limits);
      lower = std::max(lower, r.lower);
      upper = std::max(upper, r.upper);
      points += r.points;
      splits += r.splits;
    }
  }
  return {lower, std::max(lower, upper), points, splits};
}

}  // namespace

DirectedHausdorff directed_hausdorff(const SurfaceIndex& from, const SurfaceIndex& to, const HausdorffOptions& options,
                                     bool matched, double reached) {
  const int threads = thread_count(options);
  VertexPass vertices = vertex_pass(from, to, matched, threads);
  // First the distance within the error bound; then, only if the tolerance lies between
  // its bounds, the pieces that could hold a point beyond it, each measured against the
  // farthest point the first pass found anywhere (so that a triangle need not find it
  // again on its own). Each pass is deterministic, so both are.
  Limits limits{std::max(reached, vertices.max), options.tolerance, options.error_bound, false};
  TriangleResult r = triangle_pass(from, to, vertices, limits, matched, threads);
  if (r.lower <= options.tolerance && r.upper > options.tolerance) {
    limits = {r.lower, options.tolerance, options.error_bound, true};
    const TriangleResult decided = triangle_pass(from, to, vertices, limits, matched, threads);
    r = {std::max(r.lower, decided.lower), std::min(r.upper, decided.upper), r.points + decided.points,
         r.splits + decided.splits};
  }
  DirectedHausdorff out;
  out.lower = r.lower;
  out.upper = std::max(r.lower, r.upper);
  out.vertex_distances = by_mesh_vertex(from, vertices.distance);
  out.points = vertices.points + r.points;
  out.split_triangles = r.splits;
  return out;
}

}  // namespace ffd
