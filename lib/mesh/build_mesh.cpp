#include "mesh/build_mesh.h"

#include <algorithm>

#include "common/errors.h"
#include "mesh/mesh_storage.h"

namespace ffd {

std::string face_place(const std::string& file, const SoupFace& face, std::size_t index) {
  if (face.line > 0) return file + ":" + std::to_string(face.line);
  return file + ": face " + std::to_string(index);
}

namespace {

void check_face(const PolygonSoup& soup, const SoupFace& face, std::size_t index,
                const std::string& file) {
  const auto place = [&] { return face_place(file, face, index); };
  if (face.vertices.size() < 3)
    throw InputError(place() + ": a face needs at least 3 vertices, found " +
                     std::to_string(face.vertices.size()));
  for (std::uint32_t v : face.vertices)
    if (v >= soup.positions.size())
      throw InputError(place() + ": vertex index " + std::to_string(v) +
                       " is out of range (the file has " + std::to_string(soup.positions.size()) +
                       " vertices)");
  std::vector<std::uint32_t> sorted = face.vertices;
  std::sort(sorted.begin(), sorted.end());
  if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end())
    throw InputError(place() + ": the face uses one vertex twice");
  for (std::int32_t t : face.uvs)
    if (t >= static_cast<std::int32_t>(soup.uvs.size()))
      throw InputError(place() + ": texture index out of range");
  for (std::int32_t n : face.normals)
    if (n >= static_cast<std::int32_t>(soup.normals.size()))
      throw InputError(place() + ": normal index out of range");
}

// Says why Euler::add_face refused a face, for the error message.
std::string why_not_manifold(const SurfaceMesh& sm, const std::vector<VertexIndex>& vs) {
  for (std::size_t i = 0; i < vs.size(); ++i) {
    VertexIndex a = vs[i], b = vs[(i + 1) % vs.size()];
    auto h = sm.halfedge(a, b);
    if (h != SurfaceMesh::null_halfedge() && !sm.is_border(h))
      return "edge (" + std::to_string(a.idx()) + ", " + std::to_string(b.idx()) +
             ") already has a face on this side: the mesh is non-manifold there or its faces "
             "are inconsistently oriented";
  }
  return "a vertex would join two separate fans of faces (a non-manifold vertex)";
}

}  // namespace

Mesh build_mesh(const PolygonSoup& soup, const std::string& file) {
  Mesh mesh;
  MeshStorage& s = mesh.storage();
  SurfaceMesh& sm = s.sm;
  sm.reserve(soup.positions.size(), soup.positions.size() + soup.faces.size() * 2,
             soup.faces.size());
  for (const Eigen::Vector3d& p : soup.positions) {
    VertexIndex v = sm.add_vertex(to_point(p));
    s.rest[v] = p;
  }
  if (!soup.colors.empty()) {
    s.enable_colors();
    for (std::size_t i = 0; i < soup.colors.size(); ++i) s.color[VertexIndex(i)] = soup.colors[i];
  }
  s.uvs = soup.uvs;
  s.file_normals = soup.normals;
  s.groups = soup.groups;
  s.header = soup.header;

  std::vector<VertexIndex> vs;
  for (std::size_t fi = 0; fi < soup.faces.size(); ++fi) {
    const SoupFace& face = soup.faces[fi];
    check_face(soup, face, fi, file);
    vs.clear();
    for (std::uint32_t v : face.vertices) vs.push_back(VertexIndex(v));
    FaceIndex f = CGAL::Euler::add_face(vs, sm);
    if (f == SurfaceMesh::null_face())
      throw InputError(face_place(file, face, fi) + ": cannot add face " + std::to_string(fi) +
                       ": " + why_not_manifold(sm, vs) +
                       "; ffdtool needs an oriented 2-manifold mesh (boundaries are fine)");
    // Make the face's first corner the file's first vertex, so output keeps face order.
    HalfedgeIndex h = sm.halfedge(f);
    while (sm.target(h) != vs[0]) h = sm.next(h);
    sm.set_halfedge(f, h);
    s.group[f] = face.group;
    for (std::size_t c = 0; c < vs.size(); ++c, h = sm.next(h)) {
      if (!face.uvs.empty()) s.uv[h] = face.uvs[c];
      if (!face.normals.empty()) s.vn[h] = face.normals[c];
    }
  }
  s.file_uv_count = soup.uvs.size();
  s.file_normal_count = soup.normals.size();
  s.has_uvs = !soup.uvs.empty();
  s.has_file_normals = !soup.normals.empty();
  mesh.recompute_rest_normals(true);
  return mesh;
}

}  // namespace ffd
