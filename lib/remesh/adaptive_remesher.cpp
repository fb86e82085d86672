#include "remesh/adaptive_remesher.h"

#include <CGAL/Polygon_mesh_processing/triangulate_faces.h>

#include <algorithm>
#include <cstring>
#include <array>
#include <cmath>
#include <map>
#include <queue>

#include "common/errors.h"
#include "common/timer.h"
#include "mesh/halfedge_view_cgal.h"
#include "warp/warp_stack_storage.h"

namespace ffd {
namespace {

using Level = RefinementLevel;

// A face corner's attributes: indices into the UV and file-normal tables.
struct Corner {
  std::int32_t uv = -1;
  std::int32_t vn = -1;
};

// What a face carries besides its vertices, saved before an Euler operation rewires it.
struct FaceRecord {
  FaceIndex face;
  std::map<std::uint32_t, Corner> corners;  // by vertex
  std::int32_t group = -1;
  std::uint32_t start = 0;
};

// A scratch property, removed when it goes out of scope (on an exception too), so no
// scratch data outlives the op (mesh.h).
template <class Key, class Value>
class ScratchProperty {
public:
  ScratchProperty(SurfaceMesh& sm, const std::string& name)
      : sm_(sm), map_(sm.add_property_map<Key, Value>(name).first) {}
  ~ScratchProperty() { sm_.remove_property_map(map_); }
  ScratchProperty(const ScratchProperty&) = delete;
  ScratchProperty& operator=(const ScratchProperty&) = delete;
  SurfaceMesh::Property_map<Key, Value>& map() { return map_; }

private:
  SurfaceMesh& sm_;
  SurfaceMesh::Property_map<Key, Value> map_;
};

class Remesher {
public:
  Remesher(Mesh& mesh, HalfedgeView& view, const WarpStack& stack, const RemeshOptions& options, RemeshStats& stats,
           const std::function<void(double)>& progress)
      : mesh_(mesh), s_(view), sm_(s_.sm), stack_(stack), options_(options), stats_(stats),
        progress_(progress) {
    const double deg = M_PI / 180.0;
    eps_max_ = 1 - std::cos(options.theta_max_deg * deg);
    eps_min_ = 1 - std::cos(options.theta_min_deg * deg);
    // Midpoint trigger thresholds: a circular arc whose endpoint normals differ by θ has
    // chord L and sagitta (L/2)·tan(θ/4); the two faces' distances add to L·tan(θ/4).
    tan_max_ = std::tan(options.theta_max_deg * deg / 4);
    tan_min_ = std::tan(options.theta_min_deg * deg / 4);
    for (std::size_t k = 0; k < stack.size(); ++k)
      domains_.push_back({&stack.warp(k), warp_input_positions(s_, k), warp_input_normals(s_, k)});
    l_max_ = options.l_max ? *options.l_max : smallest_cell_extent(stack);
    stats_.l_max = l_max_;
  }

  void run();

private:
  // A warp and where the mesh's vertices are in its input space.
  struct Domain {
    const Warp* warp;
    Vec3Property input;
    Vec3Property input_normal;
  };

  Eigen::Vector3d pos(VertexIndex v) const { return to_eigen(sm_.point(v)); }
  // "Deformed" (condition a): the warps move the vertex, i.e. it lies where the
  // composed FFD is not the identity. A state, not an event: after every control point
  // went back, nothing is deformed and the refinement stack can unwind.
  bool deformed(VertexIndex v) const { return sm_.point(v) != to_point(s_.rest[v]); }
  double length(HalfedgeIndex h) const { return (pos(sm_.target(h)) - pos(sm_.source(h))).norm(); }
  bool in_domain(VertexIndex b, VertexIndex c) const;
  double midpoint_distance(HalfedgeIndex h) const;
  bool needs_refinement(HalfedgeIndex h, double len);
  // Midpoint trigger thresholds for an edge of length len.
  double refine_distance(double len) const { return options_.tolerance ? *options_.tolerance : len * tan_max_; }
  double decimate_distance(double len) const {
    if (options_.tolerance) return options_.tolerance_min ? *options_.tolerance_min : 0.5 * *options_.tolerance;
    return len * tan_min_;
  }
  bool passes_decimation(HalfedgeIndex h, double len);
  void triangulate();
  void refine();
  // The level a split of h's edge gives its midpoint, minus one: the highest level of
  // the edge's endpoints and opposite vertices (Gain & Dodgson).
  Level split_level(HalfedgeIndex h) const;
  // The longest edge of the faces on h when it is longer than h (length len), else h.
  HalfedgeIndex longer_face_edge(HalfedgeIndex h, double len) const;
  std::array<EdgeIndex, 4> split(EdgeIndex e, Level r);
  void decimate();
  bool try_decimate(VertexIndex m);
  // Progress: the scan is the first tenth; refinement and decimation share the rest in
  // proportion to their estimated work (edges queued by the scan, four new ones per
  // split, against decimation candidates).
  static constexpr double kScanShare = 0.1;
  static constexpr std::size_t kReportEvery = 1024;  // loop iterations between reports
  void report(double fraction) const {
    if (progress_) progress_(fraction);
  }
  void share_after_scan();
  FaceRecord record(FaceIndex f) const;
  void restore_start(FaceIndex f);
  void compact_tables();
  // Fills a new vertex's per-warp inputs, position and normal from its rest data.
  void evaluate(VertexIndex m);

  Mesh& mesh_;
  HalfedgeView& s_;  // the view the remesher edits; the declared attributes (levels, starts) live there
  SurfaceMesh& sm_;
  const WarpStack& stack_;
  const RemeshOptions& options_;
  RemeshStats& stats_;
  const std::function<void(double)>& progress_;
  double refine_share_ = 0;  // of the whole, after the scan
  std::vector<Domain> domains_;
  double l_max_ = 0, eps_max_ = 0, eps_min_ = 0, tan_max_ = 0, tan_min_ = 0;
  std::vector<std::uint8_t> candidate_;  // decimation candidates from the scan
  // Edges to split, longest first. Gain & Dodgson do not order ties; here lengths that
  // agree to 32 bits of mantissa (1 part in 4e9) tie, and the lowest edge index goes
  // first. Comparing exact lengths would let the last bits decide between mirror-image
  // edges, and those differ between builds that contract floating point differently
  // (an empty FFD_ARCH has no FMA): the same surface, with its new vertices numbered apart.
  struct HeapEntry {
    double key;  // the length with its low 20 mantissa bits cleared
    double len;
    std::uint32_t edge;
    HeapEntry(double length, std::uint32_t index) : key(coarse(length)), len(length), edge(index) {}
    static double coarse(double x) {
      std::uint64_t bits;
      std::memcpy(&bits, &x, sizeof bits);
      bits &= ~((std::uint64_t{1} << 20) - 1);
      std::memcpy(&x, &bits, sizeof bits);
      return x;
    }
  };
  struct HeapOrder {
    bool operator()(const HeapEntry& a, const HeapEntry& b) const {
      return a.key < b.key || (a.key == b.key && a.edge > b.edge);
    }
  };
  std::priority_queue<HeapEntry, std::vector<HeapEntry>, HeapOrder> heap_;
};

// Can some warp act on segment bc (in that warp's input space)?
bool Remesher::in_domain(VertexIndex b, VertexIndex c) const {
  for (const Domain& d : domains_)
    if (d.warp->can_act_on_segment(d.input[b], d.input[c])) return true;
  return false;
}

// Greissmair & Purgathofer's trigger (figure 5): m̄ = F(midpoint of the rest edge),
// m* = midpoint of the deformed edge, d = m̄ − m*, ε = |f̄1·d| + |f̄2·d|.
// The paper takes f̄ from the deformed faces on the edge. We take the true surface's
// tangent planes at m̄ instead: each face lies inside one rest face (refinement only
// splits rest triangles), so f̄ = cof(J) f, with f that face's rest normal and J the
// warps' Jacobian at m. On well-shaped faces the two agree to first order; next to a
// heavily refined neighbour the faces on a long edge become slivers whose deformed
// planes turn freely about the edge, and the literal test then misses a chord far off
// the surface.
//
// With a distance tolerance the measure is the chord midpoint's distance to the true
// surface itself, per face: one Gauss-Newton step of closest point, x = m + T·δ with T an
// orthonormal basis of the rest face's plane and δ = −(JT)⁺ d, then |F(x) − m*|; the
// larger over the two faces is returned. The plane distance alone is only the first
// order of it: where the warp stretches an edge unevenly, m* sits away from m̄ along the
// surface, and the surface's bending over that offset is what a distance tolerance
// promises to bound.
double Remesher::midpoint_distance(HalfedgeIndex h) const {
  const VertexIndex b = sm_.source(h), c = sm_.target(h);
  Eigen::Matrix3d J;
  const Eigen::Vector3d m = 0.5 * (s_.rest[b] + s_.rest[c]);
  const Eigen::Vector3d m_bar = stack_.evaluate(m, &J);
  const Eigen::Vector3d chord_mid = 0.5 * (pos(b) + pos(c));
  const Eigen::Vector3d d = m_bar - chord_mid;
  double sum = 0, largest = 0;
  for (HalfedgeIndex g : {h, sm_.opposite(h)}) {
    if (sm_.is_border(g)) continue;
    const Eigen::Vector3d& p0 = s_.rest[sm_.source(g)];
    const Eigen::Vector3d edge = s_.rest[sm_.target(g)] - p0;
    const Eigen::Vector3d rest_normal = edge.cross(s_.rest[sm_.target(sm_.next(g))] - p0);
    if (!options_.tolerance) {
      const Eigen::Vector3d n = cofactor_times(J, rest_normal);
      const double len = n.norm();
      if (len > 0) sum += std::abs(n.dot(d)) / len;
      continue;
    }
    const double edge_len = edge.norm(), normal_len = rest_normal.norm();
    if (!(edge_len > 0 && normal_len > 0)) continue;
    Eigen::Matrix<double, 3, 2> T;
    T.col(0) = edge / edge_len;
    T.col(1) = (rest_normal / normal_len).cross(T.col(0));
    const Eigen::Matrix<double, 3, 2> JT = J * T;
    const Eigen::Matrix2d normal_matrix = JT.transpose() * JT;
    const double det = normal_matrix.determinant();
    Eigen::Vector2d delta = Eigen::Vector2d::Zero();
    if (det > 0) delta = -(Eigen::Matrix2d{{normal_matrix(1, 1), -normal_matrix(0, 1)},
                                           {-normal_matrix(1, 0), normal_matrix(0, 0)}} *
                           (JT.transpose() * d)) /
                         det;
    const Eigen::Vector3d q = stack_.evaluate(m + T * delta, nullptr);
    largest = std::max(largest, (q - chord_mid).norm());
  }
  return options_.tolerance ? largest : sum;
}

bool Remesher::needs_refinement(HalfedgeIndex h, double len) {
  const VertexIndex b = sm_.source(h), c = sm_.target(h);
  if (len > l_max_ && in_domain(b, c)) return true;                   // (b)
  if (!deformed(b) && !deformed(c)) return false;                     // (a) needs a deformed endpoint
  if (options_.trigger == RemeshTrigger::Normal)
    return 1 - s_.normal[b].dot(s_.normal[c]) > eps_max_;               // ε = 1 − n̄1·n̄2
  return midpoint_distance(h) > refine_distance(len);
}

bool Remesher::passes_decimation(HalfedgeIndex h, double len) {
  if (!(len < l_max_)) return false;
  const VertexIndex b = sm_.source(h), c = sm_.target(h);
  if (options_.trigger == RemeshTrigger::Normal) return 1 - s_.normal[b].dot(s_.normal[c]) < eps_min_;
  return midpoint_distance(h) < decimate_distance(len);
}

FaceRecord Remesher::record(FaceIndex f) const {
  FaceRecord r;
  r.face = f;
  if (f == SurfaceMesh::null_face()) return r;
  for (HalfedgeIndex h : CGAL::halfedges_around_face(sm_.halfedge(f), sm_))
    r.corners[sm_.target(h).idx()] = {s_.uv[h], s_.vn[h]};
  r.group = s_.group[f];
  r.start = s_.start[f];
  return r;
}

void Remesher::restore_start(FaceIndex f) {
  for (HalfedgeIndex h : CGAL::halfedges_around_face(sm_.halfedge(f), sm_))
    if (sm_.target(h).idx() == s_.start[f]) {
      sm_.set_halfedge(f, h);
      return;
    }
}

// Polygon faces become triangles (CGAL, on rest positions so the choice does not depend
// on the deformation); each triangle keeps its polygon's corner attributes and group.
void Remesher::triangulate() {
  std::vector<FaceIndex> polygons;
  for (FaceIndex f : sm_.faces())
    if (sm_.degree(f) > 3) polygons.push_back(f);
  if (polygons.empty()) return;
  stats_.triangulated_faces = polygons.size();
  std::map<std::uint32_t, FaceRecord> records;
  for (FaceIndex f : polygons) records[f.idx()] = record(f);
  std::vector<std::pair<FaceIndex, FaceIndex>> made;  // (new face, its polygon)
  {
    ScratchProperty<VertexIndex, Point3> scratch(sm_, "v:ffd_rest_point");
    auto& rest_point = scratch.map();
    for (VertexIndex v : sm_.vertices()) rest_point[v] = to_point(s_.rest[v]);
    struct Visitor {
      std::vector<std::pair<FaceIndex, FaceIndex>>* made;
      FaceIndex current;
      void before_subface_creations(FaceIndex f) { current = f; }
      void after_subface_created(FaceIndex f) { made->emplace_back(f, current); }
      void after_subface_creations() {}
    };
    CGAL::Polygon_mesh_processing::triangulate_faces(
        polygons, sm_, CGAL::parameters::vertex_point_map(rest_point).visitor(Visitor{&made, FaceIndex()}));
  }

  std::vector<std::pair<FaceIndex, FaceIndex>> all = made;
  for (FaceIndex f : polygons) all.emplace_back(f, f);
  for (const auto& [face, polygon] : all) {
    const FaceRecord& r = records.at(polygon.idx());
    for (HalfedgeIndex h : CGAL::halfedges_around_face(sm_.halfedge(face), sm_)) {
      const Corner& c = r.corners.at(sm_.target(h).idx());
      s_.uv[h] = c.uv;
      s_.vn[h] = c.vn;
    }
    s_.group[face] = r.group;
    s_.start[face] = face == polygon ? r.start : sm_.target(sm_.halfedge(face)).idx();
    restore_start(face);
  }
  mesh_.mark_topology_changed();
}

// Gain & Dodgson figure 3: split bc at its rest midpoint m and connect m to a (and d).
// Returns the edges am, dm (null on a boundary), bm, cm.
std::array<EdgeIndex, 4> Remesher::split(EdgeIndex e, Level r) {
  const HalfedgeIndex h = sm_.halfedge(e);
  const VertexIndex b = sm_.source(h), c = sm_.target(h);
  const FaceRecord side1 = record(sm_.face(h)), side2 = record(sm_.face(sm_.opposite(h)));
  const bool has1 = side1.face != SurfaceMesh::null_face(), has2 = side2.face != SurfaceMesh::null_face();
  const VertexIndex a = has1 ? sm_.target(sm_.next(h)) : VertexIndex();  // d is on side 2

  // The new corners' attributes, interpolated per side; shared when both sides share
  // the edge's attributes (no seam), so no seam appears where there was none.
  const auto new_uv = [&](const FaceRecord& side) -> std::int32_t {
    const std::int32_t tb = side.corners.at(b.idx()).uv, tc = side.corners.at(c.idx()).uv;
    if (tb < 0 || tc < 0) return -1;
    s_.uvs.push_back(0.5 * (s_.uvs[tb] + s_.uvs[tc]));
    return static_cast<std::int32_t>(s_.uvs.size() - 1);
  };
  const auto new_vn = [&](const FaceRecord& side) -> std::int32_t {
    const std::int32_t nb = side.corners.at(b.idx()).vn, nc = side.corners.at(c.idx()).vn;
    if (nb < 0 || nc < 0) return -1;
    const Eigen::Vector3d n = s_.file_normals[nb] + s_.file_normals[nc];
    s_.file_normals.push_back(n.norm() > 0 ? Eigen::Vector3d(n.normalized()) : s_.file_normals[nb]);
    return static_cast<std::int32_t>(s_.file_normals.size() - 1);
  };
  Corner m1, m2;
  if (has1) m1 = {new_uv(side1), new_vn(side1)};
  if (has2) {
    const auto same = [&](auto member) {
      return has1 && side1.corners.at(b.idx()).*member == side2.corners.at(b.idx()).*member &&
             side1.corners.at(c.idx()).*member == side2.corners.at(c.idx()).*member;
    };
    m2.uv = same(&Corner::uv) ? m1.uv : new_uv(side2);
    m2.vn = same(&Corner::vn) ? m1.vn : new_vn(side2);
  }

  const HalfedgeIndex hnew = CGAL::Euler::split_edge(h, sm_);  // b→m (new edge), then h: m→c
  const VertexIndex m = sm_.target(hnew);
  s_.rest[m] = 0.5 * (s_.rest[b] + s_.rest[c]);
  const Eigen::Vector3d n = s_.rest_normal[b] + s_.rest_normal[c];
  s_.rest_normal[m] = n.norm() > 0 ? Eigen::Vector3d(n.normalized()) : Eigen::Vector3d::Zero();
  if (s_.has_colors) s_.color[m] = 0.5f * (s_.color[b] + s_.color[c]);
  s_.vertex_level[m] = r;
  s_.edge_level[sm_.edge(hnew)] = s_.edge_level[e];  // bm and cm keep bc's level

  std::array<EdgeIndex, 4> edges{EdgeIndex(), EdgeIndex(), sm_.edge(hnew), e};
  if (has1) {
    const HalfedgeIndex ma = CGAL::Euler::split_face(hnew, sm_.next(h), sm_);
    edges[0] = sm_.edge(ma);
    s_.edge_level[edges[0]] = r;
  }
  if (has2) {
    const HalfedgeIndex md = CGAL::Euler::split_face(sm_.opposite(h), sm_.next(sm_.opposite(hnew)), sm_);
    edges[1] = sm_.edge(md);
    s_.edge_level[edges[1]] = r;
  }
  // Corner attributes, groups and first vertices of the (up to) four faces around m.
  for (HalfedgeIndex around : CGAL::halfedges_around_target(sm_.halfedge(m), sm_)) {
    const FaceIndex f = sm_.face(around);
    if (f == SurfaceMesh::null_face()) continue;
    bool on_side1 = false;
    for (VertexIndex v : CGAL::vertices_around_face(sm_.halfedge(f), sm_)) on_side1 = on_side1 || v == a;
    if (!has1) on_side1 = false;
    const FaceRecord& side = on_side1 ? side1 : side2;
    const Corner& mc = on_side1 ? m1 : m2;
    for (HalfedgeIndex g : CGAL::halfedges_around_face(sm_.halfedge(f), sm_)) {
      const VertexIndex v = sm_.target(g);
      const Corner& corner = v == m ? mc : side.corners.at(v.idx());
      s_.uv[g] = corner.uv;
      s_.vn[g] = corner.vn;
    }
    s_.group[f] = side.group;
    s_.start[f] = f == side.face ? side.start : sm_.target(sm_.halfedge(f)).idx();
    restore_start(f);
  }
  evaluate(m);
  return edges;
}

void Remesher::evaluate(VertexIndex m) {
  Eigen::Vector3d x = s_.rest[m], n = s_.rest_normal[m];
  stack_.evaluate_point(x, n, [&](std::size_t k, const Eigen::Vector3d& xk, const Eigen::Vector3d& nk) {
    domains_[k].input[m] = xk;
    domains_[k].input_normal[m] = nk;
  });
  sm_.point(m) = to_point(x);
  s_.normal[m] = n;
}

Level Remesher::split_level(HalfedgeIndex h) const {
  Level r = std::max(s_.vertex_level[sm_.source(h)], s_.vertex_level[sm_.target(h)]);
  for (HalfedgeIndex g : {h, sm_.opposite(h)})
    if (!sm_.is_border(g)) r = std::max(r, s_.vertex_level[sm_.target(sm_.next(g))]);
  return r;
}

HalfedgeIndex Remesher::longer_face_edge(HalfedgeIndex h, double len) const {
  // Longer as the heap orders: a strictly greater key, so that the edge returned is
  // popped before h comes back (lengths that tie in the heap stay with h).
  HalfedgeIndex longest = h;
  double longest_key = HeapEntry::coarse(len);
  for (HalfedgeIndex g : {h, sm_.opposite(h)}) {
    if (sm_.is_border(g)) continue;
    for (HalfedgeIndex k : {sm_.next(g), sm_.prev(g)}) {
      const double key = HeapEntry::coarse(length(k));
      if (key > longest_key) {
        longest = k;
        longest_key = key;
      }
    }
  }
  return longest;
}

void Remesher::refine() {
  std::size_t popped = 0;
  while (!heap_.empty()) {
    if (progress_ && ++popped % kReportEvery == 0)
      report(kScanShare + refine_share_ * static_cast<double>(popped) / static_cast<double>(popped + heap_.size()));
    const double len = heap_.top().len;
    const std::uint32_t index = heap_.top().edge;
    heap_.pop();
    const EdgeIndex e(index);
    const HalfedgeIndex h = sm_.halfedge(e);
    if (length(h) != len) continue;  // split since it was pushed; its halves were pushed then
    const Level r = split_level(h);
    if (options_.longest_edge_first) {
      const HalfedgeIndex longer = longer_face_edge(h, len);
      if (longer != h && split_level(longer) + 1 <= options_.max_level) {
        // The longer edge goes first, whether or not it triggers (the closure of
        // longest-edge bisection); this one comes back after it with new faces.
        heap_.emplace(len, index);
        heap_.emplace(length(longer), sm_.edge(longer).idx());
        continue;
      }
    }
    if (r + 1 > options_.max_level) {
      ++stats_.max_level_hits;
      continue;
    }
    const auto edges = split(e, static_cast<Level>(r + 1));
    ++stats_.refinements;
    std::vector<EdgeIndex> tested(edges.begin(), edges.end());
    // The midpoint trigger also reads the faces on an edge, so the outer edges of the split
    // (ab, ac, db, dc), whose faces just changed, are tested again.
    if (options_.trigger == RemeshTrigger::Midpoint) {
      const VertexIndex m = sm_.target(sm_.halfedge(edges[2])) == sm_.source(sm_.halfedge(edges[3]))
                                ? sm_.target(sm_.halfedge(edges[2]))
                                : sm_.source(sm_.halfedge(edges[2]));
      for (HalfedgeIndex g : CGAL::halfedges_around_target(sm_.halfedge(m), sm_))
        if (!sm_.is_border(g)) tested.push_back(sm_.edge(sm_.prev(g)));
    }
    for (EdgeIndex ne : tested) {
      if (ne == EdgeIndex()) continue;
      const HalfedgeIndex nh = sm_.halfedge(ne);
      const double nl = length(nh);
      ++stats_.edges_tested;
      if (needs_refinement(nh, nl)) heap_.emplace(nl, ne.idx());
    }
  }
}

// The exact reverse of split (figure 3 backwards): m, with level-r edges am, dm and
// lower edges bm, cm of one level, goes; bc comes back with its level and edge index.
bool Remesher::try_decimate(VertexIndex m) {
  const Level r = s_.vertex_level[m];
  std::vector<HalfedgeIndex> out;  // m → neighbour, in cyclic order
  for (HalfedgeIndex h : CGAL::halfedges_around_target(sm_.halfedge(m), sm_)) out.push_back(sm_.opposite(h));
  const bool boundary = sm_.is_border(m);
  const std::size_t n = out.size();
  if (n != (boundary ? 3u : 4u)) return false;
  std::vector<std::size_t> high, low;
  for (std::size_t i = 0; i < n; ++i) {
    if (s_.vertex_level[sm_.target(out[i])] > r) return false;
    const Level el = s_.edge_level[sm_.edge(out[i])];
    if (el == r)
      high.push_back(i);
    else if (el < r)
      low.push_back(i);
    else
      return false;
  }
  if (low.size() != 2 || high.size() != n - 2) return false;
  if (s_.edge_level[sm_.edge(out[low[0]])] != s_.edge_level[sm_.edge(out[low[1]])]) return false;
  if (boundary) {
    if (!sm_.is_border(sm_.edge(out[low[0]])) || !sm_.is_border(sm_.edge(out[low[1]]))) return false;
  } else if ((low[1] - low[0]) != 2) {
    return false;  // b and c must be opposite around m
  }
  for (HalfedgeIndex h : out) {
    ++stats_.edges_tested;
    if (!passes_decimation(h, length(h))) return false;
  }
  // The guard: the restored edge bc must not need refining at once.
  const VertexIndex b = sm_.target(out[low[0]]), c = sm_.target(out[low[1]]);
  {
    const double bc = (pos(b) - pos(c)).norm();
    ++stats_.edges_tested;
    if (bc > l_max_ && in_domain(b, c)) return false;
    if ((deformed(b) || deformed(c)) && options_.trigger == RemeshTrigger::Normal &&
        1 - s_.normal[b].dot(s_.normal[c]) > eps_max_)
      return false;
  }
  if (options_.trigger == RemeshTrigger::Midpoint && (deformed(b) || deformed(c))) {
    // The restored edge's midpoint test needs the edge itself; check it on the chord.
    const Eigen::Vector3d m_bar = stack_.evaluate(0.5 * (s_.rest[b] + s_.rest[c]), nullptr);
    const Eigen::Vector3d chord_mid = 0.5 * (pos(b) + pos(c));
    if (2 * (m_bar - chord_mid).norm() > refine_distance((pos(b) - pos(c)).norm())) return false;
  }

  // The corners of the faces around m as its split set them: per level-r edge's side,
  // the attributes of that side's original face at its own vertices.
  std::vector<std::map<std::uint32_t, Corner>> sides;
  std::vector<FaceIndex> kept;
  for (std::size_t i : high) {
    HalfedgeIndex h = out[i];  // m → a (or m → d)
    std::map<std::uint32_t, Corner> corners;
    for (HalfedgeIndex g : {h, sm_.opposite(h)})
      for (HalfedgeIndex k : CGAL::halfedges_around_face(g, sm_))
        if (sm_.target(k) != m) corners[sm_.target(k).idx()] = {s_.uv[k], s_.vn[k]};
    sides.push_back(std::move(corners));
    // Keep the older (lower index) face; join_face removes face(opposite(h)).
    if (sm_.face(sm_.opposite(h)).idx() < sm_.face(h).idx()) h = sm_.opposite(h);
    kept.push_back(sm_.face(h));
    CGAL::Euler::join_face(h, sm_);
  }
  // Remove the newer of bm, cm with m; the older edge becomes bc again.
  const HalfedgeIndex to_b = out[low[0]], to_c = out[low[1]];
  CGAL::Euler::join_vertex(sm_.edge(to_b).idx() > sm_.edge(to_c).idx() ? to_b : to_c, sm_);
  for (std::size_t i = 0; i < kept.size(); ++i) {
    for (HalfedgeIndex k : CGAL::halfedges_around_face(sm_.halfedge(kept[i]), sm_)) {
      const Corner& corner = sides[i].at(sm_.target(k).idx());
      s_.uv[k] = corner.uv;
      s_.vn[k] = corner.vn;
    }
    restore_start(kept[i]);
  }
  return true;
}

void Remesher::decimate() {
  std::vector<VertexIndex> order;
  for (std::size_t v = 0; v < candidate_.size(); ++v)
    if (candidate_[v] && s_.vertex_level[VertexIndex(static_cast<std::uint32_t>(v))] > 0)
      order.push_back(VertexIndex(static_cast<std::uint32_t>(v)));
  std::stable_sort(order.begin(), order.end(), [&](VertexIndex x, VertexIndex y) {
    return s_.vertex_level[x] > s_.vertex_level[y];
  });
  const double start = kScanShare + refine_share_;
  for (std::size_t k = 0; k < order.size(); ++k) {
    if (progress_ && (k + 1) % kReportEvery == 0)
      report(start + (1 - start) * static_cast<double>(k) / static_cast<double>(order.size()));
    if (!sm_.is_removed(order[k]) && try_decimate(order[k])) ++stats_.decimations;
  }
}

void Remesher::share_after_scan() {
  const double refine_work = 4.0 * static_cast<double>(heap_.size());
  double decimate_work = 0;
  for (std::uint8_t c : candidate_) decimate_work += c;
  const double total = refine_work + decimate_work;
  refine_share_ = (1 - kScanShare) * (total > 0 ? refine_work / total : 0.5);
  report(kScanShare);
}

// Drops table entries made by refinement that no corner uses any more; the file's own
// entries stay, used or not.
void Remesher::compact_tables() {
  const auto compact = [&](auto& table, std::size_t keep, SurfaceMesh::Property_map<HalfedgeIndex, std::int32_t>& prop) {
    if (table.size() <= keep) return;
    std::vector<std::int32_t> remap(table.size(), -1);
    for (HalfedgeIndex h : sm_.halfedges())
      if (prop[h] >= 0) remap[prop[h]] = 1;
    std::size_t next = 0;
    for (std::size_t i = 0; i < table.size(); ++i)
      if (i < keep || remap[i] == 1) {
        table[next] = table[i];
        remap[i] = static_cast<std::int32_t>(next++);
      }
    table.resize(next);
    for (HalfedgeIndex h : sm_.halfedges())
      if (prop[h] >= 0) prop[h] = remap[prop[h]];
  };
  compact(s_.uvs, s_.file_uv_count, s_.uv);
  compact(s_.file_normals, s_.file_normal_count, s_.vn);
}

void Remesher::run() {
  if (!(l_max_ > 0))
    throw InputError("l_max is \"auto\" but no lattice is on the warp stack; give l_max as a length", {"l_max"});
  stats_.faces_before = sm_.number_of_faces();
  triangulate();

  Stopwatch clock;
  candidate_.assign(sm_.number_of_vertices(), 0);
  const double edge_count = static_cast<double>(sm_.number_of_edges());
  std::size_t scanned = 0;
  for (EdgeIndex e : sm_.edges()) {
    if (progress_ && ++scanned % kReportEvery == 0) report(kScanShare * static_cast<double>(scanned) / edge_count);
    const HalfedgeIndex h = sm_.halfedge(e);
    const double len = length(h);
    ++stats_.edges_tested;
    if (needs_refinement(h, len)) {
      heap_.emplace(len, e.idx());
    } else if (passes_decimation(h, len)) {
      candidate_[sm_.source(h).idx()] = 1;
      candidate_[sm_.target(h).idx()] = 1;
    }
  }
  stats_.ms_test = clock.ms();
  if (progress_) share_after_scan();

  clock.restart();
  refine();
  stats_.ms_refine = clock.ms();
  report(kScanShare + refine_share_);

  clock.restart();
  decimate();
  if (sm_.has_garbage()) sm_.collect_garbage();
  compact_tables();
  stats_.ms_decimate = clock.ms();

  if (stats_.refinements || stats_.decimations) mesh_.mark_topology_changed();
  for (VertexIndex v : sm_.vertices()) stats_.highest_level = std::max<int>(stats_.highest_level, s_.vertex_level[v]);
  stats_.faces_after = sm_.number_of_faces();
  report(1);
}

}  // namespace

double smallest_cell_extent(const WarpStack& stack) {
  double best = 0;
  for (std::size_t k = 0; k < stack.size(); ++k) {
    const double size = stack.warp(k).feature_size();
    if (size > 0 && (best == 0 || size < best)) best = size;
  }
  return best;
}

RemeshStats adaptive_remesh(Mesh& mesh, HalfedgeCache& cache, const WarpStack& stack, const RemeshOptions& options,
                            const std::function<void(double)>& progress) {
  RemeshStats stats;
  HalfedgeView& view = halfedge_view(mesh, cache);
  Remesher(mesh, view, stack, options, stats, progress).run();
  write_back(view, mesh, stats.triangulated_faces > 0 || stats.refinements > 0 || stats.decimations > 0, cache);
  return stats;
}

std::vector<int> vertex_levels(const Mesh& mesh) {
  std::vector<int> levels(mesh.num_vertices(), 0);
  const std::vector<RefinementLevel>& stored = mesh.vertex_levels();
  for (std::size_t v = 0; v < stored.size() && v < levels.size(); ++v) levels[v] = stored[v];
  return levels;
}

std::vector<Eigen::Vector3f> level_colors(const Mesh& mesh, int top_level) {
  const std::vector<int> levels = vertex_levels(mesh);
  std::vector<Eigen::Vector3f> colors(levels.size());
  // Level 0 grey; then a blue → cyan → green → yellow → red ramp up to top_level.
  static const Eigen::Vector3f ramp[] = {{0.2f, 0.3f, 1.0f}, {0.0f, 0.8f, 0.9f}, {0.2f, 0.8f, 0.2f},
                                         {1.0f, 0.85f, 0.1f}, {0.9f, 0.1f, 0.1f}};
  for (std::size_t v = 0; v < levels.size(); ++v) {
    if (levels[v] == 0) {
      colors[v] = Eigen::Vector3f(0.75f, 0.75f, 0.75f);
      continue;
    }
    const double t = top_level > 1 ? std::min(1.0, (levels[v] - 1.0) / (top_level - 1.0)) : 1.0;
    const double x = t * 4;
    const int i = std::min(3, static_cast<int>(x));
    const float f = static_cast<float>(x - i);
    colors[v] = (1 - f) * ramp[i] + f * ramp[i + 1];
  }
  return colors;
}

}  // namespace ffd
