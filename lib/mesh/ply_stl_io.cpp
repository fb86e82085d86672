#include "mesh/ply_stl_io.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>

#include "common/numbers.h"
#include "mesh/text_sink.h"

namespace ffd {

void write_ply(std::ostream& os, const Mesh& mesh, const Eigen::Matrix3Xd* normals, VertexColors colors) {
  TextSink out(os);
  out.put("ply\nformat ascii 1.0\ncomment written by ffdtool\nelement vertex ");
  out.integer(mesh.num_vertices());
  out.put("\nproperty double x\nproperty double y\nproperty double z\n");
  if (normals) out.put("property double nx\nproperty double ny\nproperty double nz\n");
  if (colors) out.put("property uchar red\nproperty uchar green\nproperty uchar blue\n");
  out.put("element face ");
  out.integer(mesh.num_faces());
  out.put("\nproperty list uchar int vertex_indices\nend_header\n");
  const ConstVec3Array p = mesh.positions();
  for (Eigen::Index i = 0; i < p.cols(); ++i) {
    for (int k = 0; k < 3; ++k) {
      if (k) out.put(' ');
      out.number(p(k, i));
    }
    if (normals)
      for (int k = 0; k < 3; ++k) {
        out.put(' ');
        out.number((*normals)(k, i));
      }
    if (colors) {
      const Eigen::Vector3f& c = (*colors)[static_cast<std::size_t>(i)];
      for (int k = 0; k < 3; ++k) {
        out.put(' ');
        out.integer(static_cast<std::int64_t>(std::lround(std::clamp(c[k], 0.0f, 1.0f) * 255.0f)));
      }
    }
    out.put('\n');
  }
  const MeshElements& el = mesh.elements();
  for (std::size_t f = 0; f < el.size(); ++f) {
    if (el.kinds[f] != ElementKind::Polygon) continue;  // refused before writing (check_writable)
    out.integer(el.degree(f));
    for (std::uint32_t c = el.begin(f); c < el.end(f); ++c) {
      out.put(' ');
      out.integer(el.corners[c]);
    }
    out.put('\n');
  }
  out.flush();
}

void write_stl(std::ostream& os, const Mesh& mesh) {
  const ConstVec3Array p = mesh.positions();
  TextSink out(os);
  out.put("solid ffdtool\n");
  const auto put_vec = [&out](const Eigen::Vector3d& v) {
    for (int k = 0; k < 3; ++k) {
      out.put(' ');
      out.number(v[k]);
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
      out.put("facet normal");
      put_vec(n);
      out.put("\n outer loop\n  vertex");
      put_vec(a);
      out.put("\n  vertex");
      put_vec(b);
      out.put("\n  vertex");
      put_vec(c);
      out.put("\n endloop\nendfacet\n");
    }
  }
  out.put("endsolid ffdtool\n");
  out.flush();
}

}  // namespace ffd
