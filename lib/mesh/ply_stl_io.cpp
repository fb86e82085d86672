#include "mesh/ply_stl_io.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>

#include "common/numbers.h"

namespace ffd {

void write_ply(std::ostream& os, const Mesh& mesh, const Eigen::Matrix3Xd* normals, VertexColors colors) {
  std::string out = "ply\nformat ascii 1.0\ncomment written by ffdtool\n";
  out += "element vertex " + std::to_string(mesh.num_vertices()) + "\n";
  out += "property double x\nproperty double y\nproperty double z\n";
  if (normals) out += "property double nx\nproperty double ny\nproperty double nz\n";
  if (colors) out += "property uchar red\nproperty uchar green\nproperty uchar blue\n";
  out += "element face " + std::to_string(mesh.num_faces()) + "\n";
  out += "property list uchar int vertex_indices\nend_header\n";
  const ConstVec3Array p = mesh.positions();
  for (Eigen::Index i = 0; i < p.cols(); ++i) {
    for (int k = 0; k < 3; ++k) {
      if (k) out += ' ';
      append_number(out, p(k, i));
    }
    if (normals)
      for (int k = 0; k < 3; ++k) {
        out += ' ';
        append_number(out, (*normals)(k, i));
      }
    if (colors) {
      const Eigen::Vector3f& c = (*colors)[static_cast<std::size_t>(i)];
      for (int k = 0; k < 3; ++k)
        out += ' ' + std::to_string(std::lround(std::clamp(c[k], 0.0f, 1.0f) * 255.0f));
    }
    out += '\n';
  }
  const MeshElements& el = mesh.elements();
  for (std::size_t f = 0; f < el.size(); ++f) {
    if (el.kinds[f] != ElementKind::Polygon) continue;  // refused before writing (check_writable)
    out += std::to_string(el.degree(f));
    for (std::uint32_t c = el.begin(f); c < el.end(f); ++c) out += ' ' + std::to_string(el.corners[c]);
    out += '\n';
  }
  os.write(out.data(), static_cast<std::streamsize>(out.size()));
}

void write_stl(std::ostream& os, const Mesh& mesh) {
  const ConstVec3Array p = mesh.positions();
  std::string out = "solid ffdtool\n";
  const auto append_vec = [&out](const Eigen::Vector3d& v) {
    for (int k = 0; k < 3; ++k) {
      out += ' ';
      append_number(out, v[k]);
    }
  };
  const MeshElements& el = mesh.elements();
  for (std::size_t f = 0; f < el.size(); ++f) {
    if (el.kinds[f] != ElementKind::Polygon) continue;
    const std::uint32_t* ids = el.vertices(f);
    for (std::size_t i = 1; i + 1 < el.degree(f); ++i) {
      const Eigen::Vector3d a = p.col(ids[0]), b = p.col(ids[i]), c = p.col(ids[i + 1]);
      Eigen::Vector3d n = (b - a).cross(c - a);
      if (n.norm() > 0) n.normalize();
      out += "facet normal";
      append_vec(n);
      out += "\n outer loop\n  vertex";
      append_vec(a);
      out += "\n  vertex";
      append_vec(b);
      out += "\n  vertex";
      append_vec(c);
      out += "\n endloop\nendfacet\n";
    }
  }
  out += "endsolid ffdtool\n";
  os.write(out.data(), static_cast<std::streamsize>(out.size()));
}

}  // namespace ffd
