#include "mesh/halfedge_view.h"

#include <algorithm>
#include <cstring>
#include <type_traits>

#include "common/errors.h"
#include "mesh/build_mesh.h"
#include "mesh/halfedge_view_cgal.h"

namespace ffd {

HalfedgeView::HalfedgeView() {
  rest = sm.add_property_map<VertexIndex, Eigen::Vector3d>("v:rest", Eigen::Vector3d::Zero()).first;
  rest_normal = sm.add_property_map<VertexIndex, Eigen::Vector3d>("v:rest_normal", Eigen::Vector3d::Zero()).first;
  normal = sm.add_property_map<VertexIndex, Eigen::Vector3d>("v:normal", Eigen::Vector3d::Zero()).first;
  uv = sm.add_property_map<HalfedgeIndex, std::int32_t>("h:uv", -1).first;
  vn = sm.add_property_map<HalfedgeIndex, std::int32_t>("h:vn", -1).first;
  group = sm.add_property_map<FaceIndex, std::int32_t>("f:group", -1).first;
  vertex_level = sm.add_property_map<VertexIndex, RefinementLevel>(mesh_attribute::kVertexLevel, 0).first;
  edge_level = sm.add_property_map<EdgeIndex, RefinementLevel>(mesh_attribute::kEdgeLevel, 0).first;
  start = sm.add_property_map<FaceIndex, std::uint32_t>(mesh_attribute::kFaceStart, 0).first;
}

HalfedgeView::HalfedgeView(const HalfedgeView& other)
    : sm(other.sm),
      uvs(other.uvs),
      file_normals(other.file_normals),
      file_uv_count(other.file_uv_count),
      file_normal_count(other.file_normal_count),
      has_colors(other.has_colors),
      face_element(other.face_element) {
  bind();
}

void HalfedgeView::bind() {
  rest = sm.property_map<VertexIndex, Eigen::Vector3d>("v:rest").first;
  rest_normal = sm.property_map<VertexIndex, Eigen::Vector3d>("v:rest_normal").first;
  normal = sm.property_map<VertexIndex, Eigen::Vector3d>("v:normal").first;
  uv = sm.property_map<HalfedgeIndex, std::int32_t>("h:uv").first;
  vn = sm.property_map<HalfedgeIndex, std::int32_t>("h:vn").first;
  group = sm.property_map<FaceIndex, std::int32_t>("f:group").first;
  vertex_level = sm.property_map<VertexIndex, RefinementLevel>(mesh_attribute::kVertexLevel).first;
  edge_level = sm.property_map<EdgeIndex, RefinementLevel>(mesh_attribute::kEdgeLevel).first;
  start = sm.property_map<FaceIndex, std::uint32_t>(mesh_attribute::kFaceStart).first;
  const auto colors = sm.property_map<VertexIndex, Eigen::Vector3f>("v:color");
  has_colors = colors.second;
  if (has_colors) color = colors.first;
}

void HalfedgeView::enable_colors() {
  if (has_colors) return;
  color = sm.add_property_map<VertexIndex, Eigen::Vector3f>("v:color", kDefaultColor).first;
  has_colors = true;
}

namespace {

constexpr char kAttributePrefix[] = "v:attr:";

}  // namespace

Vec3Property HalfedgeView::vec3_attribute(const std::string& name) {
  return sm.add_property_map<VertexIndex, Eigen::Vector3d>(kAttributePrefix + name, Eigen::Vector3d::Zero()).first;
}

HalfedgeCache::HalfedgeCache() = default;
HalfedgeCache::~HalfedgeCache() = default;
HalfedgeCache::HalfedgeCache(HalfedgeCache&&) noexcept = default;
HalfedgeCache& HalfedgeCache::operator=(HalfedgeCache&&) noexcept = default;

HalfedgeCache HalfedgeCache::clone() const {
  HalfedgeCache copy;
  if (view_) copy.view_ = std::make_shared<HalfedgeView>(*view_);
  copy.version_ = version_;
  return copy;
}

void HalfedgeCache::keep(std::shared_ptr<HalfedgeView> view, const Mesh& mesh) {
  view_ = std::move(view);
  version_ = mesh.topology_version();
}

std::vector<std::string> attribute_names(const Mesh& mesh, const HalfedgeCache& cache) {
  std::vector<std::string> names = mesh.attribute_names();
  if (cache.view())
    for (const std::string& n : view_property_names(*cache.view())) names.push_back("view " + n);
  std::sort(names.begin(), names.end());
  return names;
}

std::vector<std::string> view_property_names(const HalfedgeView& view) {
  std::vector<std::string> names;
  for (const std::string& n : view.sm.properties<VertexIndex>()) names.push_back(n);
  for (const std::string& n : view.sm.properties<HalfedgeIndex>()) names.push_back(n);
  for (const std::string& n : view.sm.properties<EdgeIndex>()) names.push_back(n);
  for (const std::string& n : view.sm.properties<FaceIndex>()) names.push_back(n);
  std::sort(names.begin(), names.end());
  return names;
}

namespace {

// The corner of face f at vertex v (its halfedge with target v).
HalfedgeIndex corner_at(const SurfaceMesh& sm, FaceIndex f, std::uint32_t v) {
  for (HalfedgeIndex h : CGAL::halfedges_around_face(sm.halfedge(f), sm))
    if (sm.target(h).idx() == v) return h;
  return sm.halfedge(f);
}

constexpr char kPoints[] = "v:point";  // the view's points: its current positions

Eigen::Vector3d element(const Eigen::Matrix3Xd& m, Eigen::Index i) { return m.col(i); }
template <class T>
const T& element(const std::vector<T>& v, Eigen::Index i) {
  return v[static_cast<std::size_t>(i)];
}
void set_element(Eigen::Matrix3Xd& m, Eigen::Index i, const Eigen::Vector3d& x) { m.col(i) = x; }
template <class T>
void set_element(std::vector<T>& v, Eigen::Index i, const T& x) {
  v[static_cast<std::size_t>(i)] = x;
}

// One declared per-vertex array into the view's property of its name (created with the
// array's default if missing); an empty optional array sets the default where the view
// has the property, and adds none.
template <class S, class V>
void array_to_view(const Mesh& mesh, const VertexArray<S, V>& a, SurfaceMesh& sm) {
  const S& array = mesh.*a.member;
  if constexpr (std::is_same_v<V, Eigen::Vector3d>)
    if (std::strcmp(a.name, kPoints) == 0) {
      for (VertexIndex v : sm.vertices()) sm.point(v) = to_point(element(array, v.idx()));
      return;
    }
  const bool absent = a.optional && array.size() == 0;
  if (absent && !sm.property_map<VertexIndex, V>(a.name).second) return;
  auto map = sm.add_property_map<VertexIndex, V>(a.name, a.fallback).first;
  for (VertexIndex v : sm.vertices()) map[v] = absent ? a.fallback : V(element(array, v.idx()));
}

// The view's property back into the declared array (sized to the view's vertices).
template <class S, class V>
void array_from_view(const SurfaceMesh& sm, const VertexArray<S, V>& a, Mesh& mesh) {
  S& array = mesh.*a.member;
  if constexpr (std::is_same_v<V, Eigen::Vector3d>)
    if (std::strcmp(a.name, kPoints) == 0) {
      for (VertexIndex v : sm.vertices()) set_element(array, v.idx(), to_eigen(sm.point(v)));
      return;
    }
  const auto map = sm.property_map<VertexIndex, V>(a.name);
  if (!map.second) return;  // an optional array the view does not have
  if constexpr (!std::is_same_v<S, Eigen::Matrix3Xd>) array.resize(sm.number_of_vertices(), a.fallback);
  for (VertexIndex v : sm.vertices()) set_element(array, v.idx(), map.first[v]);
}

// Copies the mesh's per-vertex arrays into the view: the declared ones, then the vec3
// attributes (dropping the view's copies of attributes the mesh no longer has).
void sync_vertices(const Mesh& mesh, HalfedgeView& view) {
  SurfaceMesh& sm = view.sm;
  Mesh::for_each_vertex_array([&](const auto& a) { array_to_view(mesh, a, sm); });
  view.bind();
  std::vector<std::string> stale;
  for (const std::string& name : sm.properties<VertexIndex>())
    if (name.rfind(kAttributePrefix, 0) == 0 && !mesh.has_vec3_attribute(name.substr(sizeof kAttributePrefix - 1)))
      stale.push_back(name);
  for (const std::string& name : stale) {
    auto map = sm.property_map<VertexIndex, Eigen::Vector3d>(name).first;
    sm.remove_property_map(map);
  }
  for (const std::string& name : mesh.vec3_attribute_names()) {
    Vec3Property map = view.vec3_attribute(name);
    const ConstVec3Array a = mesh.vec3_attribute(name);
    for (VertexIndex v : sm.vertices()) map[v] = a.col(v.idx());
  }
}

// Copies the elements' corner data, groups, starts, edge levels and tables into the view.
void sync_faces(const Mesh& mesh, HalfedgeView& view) {
  SurfaceMesh& sm = view.sm;
  const MeshElements& el = mesh.elements();
  for (FaceIndex f : sm.faces()) {
    const std::size_t e = view.face_element[f.idx()];
    HalfedgeIndex h = sm.halfedge(f);  // the element's first corner (build_view, write_back)
    for (std::uint32_t c = el.begin(e); c < el.end(e); ++c, h = sm.next(h)) {
      view.uv[h] = el.uv(c);
      view.vn[h] = el.normal(c);
    }
    view.group[f] = el.group(e);
  }
  for (EdgeIndex e : sm.edges()) view.edge_level[e] = 0;
  for (const EdgeLevel& level : mesh.edge_levels()) {
    const HalfedgeIndex h = sm.halfedge(VertexIndex(level.a), VertexIndex(level.b));
    if (h != SurfaceMesh::null_halfedge()) view.edge_level[sm.edge(h)] = level.level;
  }
  view.uvs = mesh.uvs();
  view.file_normals = mesh.file_normals();
  view.file_uv_count = mesh.file_uv_count;
  view.file_normal_count = mesh.file_normal_count;
}

// A new view of the mesh's polygons, in element order. The mesh passed check_two_manifold.
std::shared_ptr<HalfedgeView> build_view(const Mesh& mesh) {
  auto view = std::make_shared<HalfedgeView>();
  SurfaceMesh& sm = view->sm;
  const MeshElements& el = mesh.elements();
  sm.reserve(static_cast<SurfaceMesh::size_type>(mesh.num_vertices()),
             static_cast<SurfaceMesh::size_type>(el.corners.size()), static_cast<SurfaceMesh::size_type>(mesh.num_faces()));
  for (std::size_t v = 0; v < mesh.num_vertices(); ++v) sm.add_vertex();
  std::vector<VertexIndex> vs;
  for (std::size_t e = 0; e < el.size(); ++e) {
    if (el.kinds[e] != ElementKind::Polygon) continue;
    vs.clear();
    for (std::uint32_t c = el.begin(e); c < el.end(e); ++c) vs.push_back(VertexIndex(el.corners[c]));
    if (CGAL::Euler::add_face(vs, sm) == SurfaceMesh::null_face())
      throw TopologyError(At{element_place(mesh.source().empty() ? "mesh" : mesh.source(), el, e)},
                          "face " + std::to_string(e) +
                              " cannot join the halfedge mesh (a vertex where separate fans of faces meet)");
    view->face_element.push_back(static_cast<std::uint32_t>(e));
  }
  // Each face starts at its element's first corner; the start persists in the cached
  // view, so a face decimation restores in a later step starts where it was.
  for (FaceIndex f : sm.faces()) {
    const std::size_t e = view->face_element[f.idx()];
    view->start[f] = el.corners[el.begin(e)];
    sm.set_halfedge(f, corner_at(sm, f, view->start[f]));
  }
  return view;
}

// True when the cached view still matches the mesh's connectivity: same counts, and each
// face's first corner is its element's first vertex.
bool cache_matches(const HalfedgeCache& cache, const Mesh& mesh) {
  if (!cache.valid_for(mesh)) return false;
  const HalfedgeView* view = cache.view();
  const SurfaceMesh& sm = view->sm;
  if (sm.number_of_vertices() != mesh.num_vertices() || sm.number_of_faces() != mesh.num_faces() ||
      sm.has_garbage() || view->face_element.size() != sm.number_of_faces())
    return false;
  const MeshElements& el = mesh.elements();
  for (FaceIndex f : sm.faces()) {
    const std::size_t e = view->face_element[f.idx()];
    if (e >= el.size() || el.degree(e) != sm.degree(f) || sm.target(sm.halfedge(f)).idx() != el.corners[el.begin(e)])
      return false;
  }
  return true;
}

}  // namespace

HalfedgeView& halfedge_view(Mesh& mesh, HalfedgeCache& cache) {
  if (!cache_matches(cache, mesh)) {
    check_two_manifold(mesh);
    cache.keep(build_view(mesh), mesh);
  }
  HalfedgeView& view = *cache.view();
  sync_vertices(mesh, view);
  sync_faces(mesh, view);
  cache.invalidate();  // until write_back: the op changes it
  return view;
}

namespace {

// Copies the view's per-vertex data into the mesh's arrays (resized to the view's count).
void write_vertices(const HalfedgeView& view, Mesh& mesh) {
  const SurfaceMesh& sm = view.sm;
  mesh.resize_vertices(sm.number_of_vertices());
  Mesh::for_each_vertex_array([&](const auto& a) { array_from_view(sm, a, mesh); });
  for (const std::string& name : mesh.vec3_attribute_names()) {
    const auto map = sm.property_map<VertexIndex, Eigen::Vector3d>(kAttributePrefix + name);
    if (!map.second) continue;
    Vec3Array a = mesh.vec3_attribute(name);
    for (VertexIndex v : sm.vertices()) a.col(v.idx()) = map.first[v];
  }
  std::vector<EdgeLevel>& levels = mesh.edge_levels();
  levels.clear();
  for (EdgeIndex e : sm.edges())
    if (view.edge_level[e] > 0) {
      const std::uint32_t a = sm.vertex(e, 0).idx(), b = sm.vertex(e, 1).idx();
      levels.push_back({std::min(a, b), std::max(a, b), view.edge_level[e]});
    }
  std::sort(levels.begin(), levels.end(), [](const EdgeLevel& x, const EdgeLevel& y) {
    return std::tie(x.a, x.b) < std::tie(y.a, y.b);
  });
  mesh.uvs() = view.uvs;
  mesh.file_normals() = view.file_normals;
  mesh.file_uv_count = view.file_uv_count;
  mesh.file_normal_count = view.file_normal_count;
}

// Appends view face f to `out`, from its first corner (sm.halfedge(f): the remesher
// keeps it at the face's start).
void append_face(const HalfedgeView& view, FaceIndex f, MeshElements& out) {
  const SurfaceMesh& sm = view.sm;
  const HalfedgeIndex first = sm.halfedge(f);
  HalfedgeIndex h = first;
  do {
    out.add_corner(sm.target(h).idx(), view.uv[h], view.vn[h]);
    h = sm.next(h);
  } while (h != first);
  out.close(ElementKind::Polygon, view.group[f]);
}

// The mesh's elements with the view's faces in the polygons' places (see write_back).
MeshElements merged_elements(HalfedgeView& view, const Mesh& mesh) {
  const SurfaceMesh& sm = view.sm;
  const MeshElements& old = mesh.elements();
  MeshElements out;
  out.reserve(sm.number_of_faces() + old.size() - mesh.num_faces(), 3);
  std::vector<std::uint32_t> face_element;
  std::uint32_t next = 0;
  const auto add_next_face = [&] {
    face_element.push_back(static_cast<std::uint32_t>(out.size()));
    append_face(view, FaceIndex(next++), out);
  };
  for (std::size_t e = 0; e < old.size(); ++e) {
    if (old.kinds[e] == ElementKind::Polygon) {
      if (next < sm.number_of_faces()) add_next_face();
      continue;
    }
    for (std::uint32_t c = old.begin(e); c < old.end(e); ++c) out.add_corner(old.corners[c], old.uv(c), old.normal(c));
    out.close(old.kinds[e], old.group(e));
  }
  while (next < sm.number_of_faces()) add_next_face();
  view.face_element = std::move(face_element);
  return out;
}

}  // namespace

void write_back(HalfedgeView& view, Mesh& mesh, bool connectivity_changed, HalfedgeCache& cache) {
  write_vertices(view, mesh);
  if (connectivity_changed) {
    mesh.set_elements(merged_elements(view, mesh));
    mesh.mark_topology_changed();
  }
  cache.revalidate(mesh);
}

SurfaceMesh surface_mesh(const Mesh& mesh) {
  check_two_manifold(mesh);
  SurfaceMesh sm = build_view(mesh)->sm;
  const ConstVec3Array p = mesh.positions();
  for (VertexIndex v : sm.vertices()) sm.point(v) = to_point(p.col(v.idx()));
  return sm;
}

Mesh mesh_from_surface(const SurfaceMesh& sm, const std::string& source) {
  PolygonSoup soup;
  for (VertexIndex v : sm.vertices()) soup.positions.push_back(to_eigen(sm.point(v)));
  for (FaceIndex f : sm.faces()) {
    for (VertexIndex v : CGAL::vertices_around_face(sm.halfedge(f), sm)) soup.elements.add_corner(v.idx());
    soup.elements.close(ElementKind::Polygon);
  }
  return build_mesh(std::move(soup), source);
}

}  // namespace ffd
