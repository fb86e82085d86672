#include "mesh/ply_stl_io.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstring>

#include "common/errors.h"
#include "common/numbers.h"
#include "mesh/text_sink.h"

namespace ffd {

namespace {

// The most corners of any polygon: PLY's usual face list count is a uchar (up to 255).
std::uint32_t max_degree(const MeshElements& el) {
  std::uint32_t most = 0;
  for (std::size_t f = 0; f < el.size(); ++f)
    if (el.kinds[f] == ElementKind::Polygon) most = std::max(most, el.degree(f));
  return most;
}

void put_ply_header(TextSink& out, const Mesh& mesh, bool normals, bool colors, bool uvs, bool binary, bool wide) {
  out.put(binary ? "ply\nformat binary_little_endian 1.0\n" : "ply\nformat ascii 1.0\n");
  out.put("comment written by ffdtool\nelement vertex ");
  out.integer(mesh.num_vertices());
  out.put("\nproperty double x\nproperty double y\nproperty double z\n");
  if (normals) out.put("property double nx\nproperty double ny\nproperty double nz\n");
  if (colors) out.put("property uchar red\nproperty uchar green\nproperty uchar blue\n");
  if (uvs) out.put("property double u\nproperty double v\n");
  out.put("element face ");
  out.integer(mesh.num_faces());
  out.put(wide ? "\nproperty list int int vertex_indices\nend_header\n"
               : "\nproperty list uchar int vertex_indices\nend_header\n");
}

// One vertex's values: x y z, then the normal, the colour and the UV when given.
void put_ply_vertex(TextSink& out, const Mesh& mesh, Eigen::Index i, const Eigen::Matrix3Xd* normals,
                    VertexColors colors, const std::vector<Eigen::Vector2d>& uvs, bool binary) {
  const ConstVec3Array p = mesh.positions();
  double values[6];
  int count = 0;
  for (int k = 0; k < 3; ++k) values[count++] = p(k, i);
  if (normals)
    for (int k = 0; k < 3; ++k) values[count++] = (*normals)(k, i);
  for (int k = 0; k < count; ++k) {
    if (binary) {
      out.raw(values[k]);
      continue;
    }
    if (k) out.put(' ');
    out.number(values[k]);
  }
  if (colors)
    for (int k = 0; k < 3; ++k) {
      const std::uint8_t c = color_byte((*colors)[static_cast<std::size_t>(i)][k]);
      if (binary) {
        out.raw(c);
        continue;
      }
      out.put(' ');
      out.integer(std::uint32_t{c});
    }
  if (!uvs.empty())
    for (int k = 0; k < 2; ++k) {
      const double t = uvs[static_cast<std::size_t>(i)][k];
      if (binary) {
        out.raw(t);
        continue;
      }
      out.put(' ');
      out.number(t);
    }
  if (!binary) out.put('\n');
}

// Polygon f's corner count and vertex indices.
void put_ply_face(TextSink& out, const MeshElements& el, std::size_t f, bool binary, bool wide) {
  if (binary) {
    if (wide) out.raw(static_cast<std::int32_t>(el.degree(f)));
    else out.raw(static_cast<std::uint8_t>(el.degree(f)));
    for (std::uint32_t c = el.begin(f); c < el.end(f); ++c) out.raw(static_cast<std::int32_t>(el.corners[c]));
    return;
  }
  out.integer(el.degree(f));
  for (std::uint32_t c = el.begin(f); c < el.end(f); ++c) {
    out.put(' ');
    out.integer(el.corners[c]);
  }
  out.put('\n');
}

}  // namespace

std::vector<Eigen::Vector2d> vertex_uvs(const Mesh& mesh) {
  if (!mesh.has_uvs()) return {};
  const MeshElements& el = mesh.elements();
  std::vector<std::int32_t> at(mesh.num_vertices(), -1);
  for (std::size_t f = 0; f < el.size(); ++f) {
    if (el.kinds[f] != ElementKind::Polygon) continue;
    for (std::uint32_t c = el.begin(f); c < el.end(f); ++c) {
      const std::int32_t t = el.uv(c);
      std::int32_t& first = at[el.corners[c]];
      if (t < 0) return {};
      if (first < 0) first = t;
      else if (mesh.uvs()[static_cast<std::size_t>(first)] != mesh.uvs()[static_cast<std::size_t>(t)]) return {};
    }
  }
  std::vector<Eigen::Vector2d> out(at.size(), Eigen::Vector2d::Zero());
  for (std::size_t v = 0; v < at.size(); ++v)
    if (at[v] >= 0) out[v] = mesh.uvs()[static_cast<std::size_t>(at[v])];
  return out;
}

void write_ply(std::ostream& os, const Mesh& mesh, const Eigen::Matrix3Xd* normals, VertexColors colors,
               bool binary) {
  TextSink out(os);
  const MeshElements& el = mesh.elements();
  const bool wide = max_degree(el) > 255;
  const std::vector<Eigen::Vector2d> uvs = vertex_uvs(mesh);
  put_ply_header(out, mesh, normals != nullptr, colors != nullptr, !uvs.empty(), binary, wide);
  // Text is formatted by the team in order (put_ordered); binary values are copies already.
  const auto vertex = [&](TextSink& sink, std::size_t i) {
    put_ply_vertex(sink, mesh, static_cast<Eigen::Index>(i), normals, colors, uvs, binary);
  };
  const auto face = [&](TextSink& sink, std::size_t f) {
    if (el.kinds[f] == ElementKind::Polygon) put_ply_face(sink, el, f, binary, wide);  // others: check_writable
  };
  if (binary) {
    for (std::size_t i = 0; i < mesh.num_vertices(); ++i) vertex(out, i);
    for (std::size_t f = 0; f < el.size(); ++f) face(out, f);
  } else {
    put_ordered(out, 0, mesh.num_vertices(), vertex);
    put_ordered(out, 0, el.size(), face);
  }
  out.flush();
}

namespace {

// Calls fn(corners, unit normal) for each triangle of element f's fan (STL holds only
// triangles; a line or point has none); a degenerate triangle's normal is zero.
template <class Fn>
void for_each_fan_triangle(const Mesh& mesh, std::size_t f, Fn fn) {
  const ConstVec3Array p = mesh.positions();
  const MeshElements& el = mesh.elements();
  if (el.kinds[f] != ElementKind::Polygon) return;
  const std::uint32_t* ids = el.vertices(f);
  for (std::size_t i = 1; i + 1 < el.degree(f); ++i) {
    const Eigen::Vector3d corners[3] = {p.col(ids[0]), p.col(ids[i]), p.col(ids[i + 1])};
    Eigen::Vector3d n = (corners[1] - corners[0]).cross(corners[2] - corners[0]);
    if (n.norm() > 0) n.normalize();
    fn(corners, n);
  }
}

// The same for every element, in element order.
template <class Fn>
void for_each_fan(const Mesh& mesh, Fn fn) {
  for (std::size_t f = 0; f < mesh.elements().size(); ++f) for_each_fan_triangle(mesh, f, fn);
}

// Binary STL: an 80-byte header (not starting with "solid", which would read as ASCII),
// the triangle count, then per triangle the unit normal and three corners as little-endian
// float32, and a zero attribute word.
void write_binary_stl(TextSink& out, const Mesh& mesh) {
  const MeshElements& el = mesh.elements();
  char header[80] = {};
  std::memcpy(header, "binary STL written by ffdtool", 29);
  out.put(std::string_view(header, sizeof header));
  std::uint64_t triangles = 0;
  for (std::size_t f = 0; f < el.size(); ++f)
    if (el.kinds[f] == ElementKind::Polygon && el.degree(f) >= 3) triangles += el.degree(f) - 2;
  if (triangles > 0xffffffffu) throw InputError("a binary STL holds at most 2^32 - 1 triangles");
  out.raw(static_cast<std::uint32_t>(triangles));
  for_each_fan(mesh, [&out](const Eigen::Vector3d* corners, const Eigen::Vector3d& n) {
    for (int k = 0; k < 3; ++k) out.raw(static_cast<float>(n[k]));
    for (int c = 0; c < 3; ++c)
      for (int k = 0; k < 3; ++k) out.raw(static_cast<float>(corners[c][k]));
    out.raw(std::uint16_t{0});
  });
}

// Element f's facets (put_ordered formats the elements in order, by the team).
void put_ascii_facets(TextSink& out, const Mesh& mesh, std::size_t f) {
  const auto put_vec = [&out](const Eigen::Vector3d& v) {
    for (int k = 0; k < 3; ++k) {
      out.put(' ');
      out.number(v[k]);
    }
  };
  for_each_fan_triangle(mesh, f, [&](const Eigen::Vector3d* corners, const Eigen::Vector3d& n) {
    out.put("facet normal");
    put_vec(n);
    out.put("\n outer loop\n  vertex");
    put_vec(corners[0]);
    out.put("\n  vertex");
    put_vec(corners[1]);
    out.put("\n  vertex");
    put_vec(corners[2]);
    out.put("\n endloop\nendfacet\n");
  });
}

void write_ascii_stl(TextSink& out, const Mesh& mesh) {
  out.put("solid ffdtool\n");
  put_ordered(out, 0, mesh.elements().size(),
              [&mesh](TextSink& sink, std::size_t f) { put_ascii_facets(sink, mesh, f); });
  out.put("endsolid ffdtool\n");
}

}  // namespace

void write_stl(std::ostream& os, const Mesh& mesh, bool binary) {
  TextSink out(os);
  if (binary) write_binary_stl(out, mesh);
  else write_ascii_stl(out, mesh);
  out.flush();
}

}  // namespace ffd
