#include "mesh/ply_stl_io.h"

#include <CGAL/IO/PLY.h>
#include <CGAL/IO/STL.h>
#include <CGAL/Surface_mesh/IO/PLY.h>

#include <algorithm>
#include <cmath>
#include <fstream>

#include "common/errors.h"
#include "common/numbers.h"
#include "mesh/mesh_storage.h"

namespace ffd {
namespace {

std::ifstream open_binary(const std::string& path) {
  std::ifstream is(path, std::ios::binary);
  if (!is) throw InputError(path + ": cannot open for reading");
  return is;
}

void check_finite(const PolygonSoup& soup, const std::string& path) {
  for (std::size_t i = 0; i < soup.positions.size(); ++i)
    if (!soup.positions[i].allFinite())
      throw InputError(path + ": vertex " + std::to_string(i) + " has a non-finite coordinate");
  for (std::size_t i = 0; i < soup.normals.size(); ++i)
    if (!soup.normals[i].allFinite())
      throw InputError(path + ": the normal of vertex " + std::to_string(i) + " is not finite");
}

}  // namespace

PolygonSoup read_ply(const std::string& path) {
  PolygonSoup soup;
  // First as a polygon soup: it reads any face list, so a non-manifold face is reported by
  // build_mesh with its index instead of as a bare "cannot read".
  {
    std::ifstream is = open_binary(path);
    std::vector<Point3> points;
    std::vector<std::vector<std::size_t>> polygons;
    std::vector<CGAL::IO::Color> colors, face_colors;  // face colours are read and dropped
    if (!CGAL::IO::read_PLY(is, points, polygons,
                            CGAL::parameters::vertex_color_output_iterator(std::back_inserter(colors))
                                .face_color_output_iterator(std::back_inserter(face_colors))
                                .verbose(false)))
      throw InputError(path + ": not a readable PLY file (CGAL's reader refused it)");
    for (const Point3& p : points) soup.positions.push_back(to_eigen(p));
    for (std::size_t i = 0; i < polygons.size(); ++i) {
      SoupFace face;
      for (std::size_t v : polygons[i]) {
        if (v >= points.size())
          throw InputError(path + ": face " + std::to_string(i) + " uses vertex " + std::to_string(v) +
                           ", out of range (the file has " + std::to_string(points.size()) + ")");
        face.vertices.push_back(static_cast<std::uint32_t>(v));
      }
      soup.faces.push_back(std::move(face));
    }
    if (colors.size() == points.size())
      for (const CGAL::IO::Color& c : colors)
        soup.colors.emplace_back(c.red() / 255.0f, c.green() / 255.0f, c.blue() / 255.0f);
  }
  // Vertex normals are only exposed by the Surface_mesh reader; it refuses non-manifold
  // input, in which case build_mesh reports the face anyway.
  {
    std::ifstream is = open_binary(path);
    SurfaceMesh tmp;
    std::string comments;
    if (CGAL::IO::read_PLY(is, tmp, comments, false) &&
        tmp.number_of_vertices() == soup.positions.size()) {
      auto normals = tmp.property_map<VertexIndex, Kernel::Vector_3>("v:normal");
      if (normals.second) {
        for (VertexIndex v : tmp.vertices()) {
          const Kernel::Vector_3& n = normals.first[v];
          soup.normals.emplace_back(n.x(), n.y(), n.z());
        }
        for (SoupFace& f : soup.faces) f.normals.assign(f.vertices.begin(), f.vertices.end());
      }
    }
  }
  check_finite(soup, path);
  return soup;
}

PolygonSoup read_stl(const std::string& path) {
  std::ifstream is = open_binary(path);
  std::vector<Point3> points;
  std::vector<std::array<std::size_t, 3>> triangles;
  if (!CGAL::IO::read_STL(is, points, triangles, CGAL::parameters::verbose(false)))
    throw InputError(path + ": not a readable STL file (CGAL's reader refused it)");
  PolygonSoup soup;
  for (const Point3& p : points) soup.positions.push_back(to_eigen(p));
  for (const auto& t : triangles) {
    SoupFace face;
    face.vertices = {static_cast<std::uint32_t>(t[0]), static_cast<std::uint32_t>(t[1]),
                     static_cast<std::uint32_t>(t[2])};
    soup.faces.push_back(std::move(face));
  }
  check_finite(soup, path);
  return soup;
}

void write_ply(std::ostream& os, const Mesh& mesh, const Eigen::Matrix3Xd* normals, VertexColors colors) {
  const MeshStorage& s = mesh.storage();
  const SurfaceMesh& sm = s.sm;
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
  for (FaceIndex f : sm.faces()) {
    out += std::to_string(sm.degree(f));
    for (VertexIndex v : CGAL::vertices_around_face(sm.halfedge(f), sm)) out += ' ' + std::to_string(v.idx());
    out += '\n';
  }
  os.write(out.data(), static_cast<std::streamsize>(out.size()));
}

void write_stl(std::ostream& os, const Mesh& mesh) {
  const ConstVec3Array p = mesh.positions();
  std::string out = "solid ffdtool\n";
  std::vector<std::uint32_t> ids;
  const auto append_vec = [&out](const Eigen::Vector3d& v) {
    for (int k = 0; k < 3; ++k) {
      out += ' ';
      append_number(out, v[k]);
    }
  };
  for (std::size_t f = 0; f < mesh.num_faces(); ++f) {
    mesh.face_vertices(f, ids);
    for (std::size_t i = 1; i + 1 < ids.size(); ++i) {
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
