// A PLY file written back faithfully (mesh/ply_source.h): every element and property in
// the file's order and types, byte for byte where nothing changed; what the reader newly
// accepts (tristrips, CR line ends, repeated names, diffuse colours); and the warning that
// names what another format cannot hold.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <sstream>

#include "mesh/build_mesh.h"
#include "mesh/mesh_io.h"
#include "mesh/ply_io.h"
#include "mesh/ply_source.h"
#include "mesh/ply_stl_io.h"
#include "test_meshes.h"

namespace ffd {
namespace {

template <typename T>
void put_value(std::string& out, T v, bool big) {
  char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));
  if (big) std::reverse(b, b + sizeof(T));
  out.append(b, sizeof(T));
}

// A square pyramid with what real exporters add: normals, RGBA, UVs under Blender's
// names, a confidence and an object id per vertex; per-face colours, a quality and a
// per-corner texcoord list; an edge element; comments and obj_info.
std::string pyramid_ply(const std::string& format) {
  const float p[5][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0.5f, 0.5f, 0.75f}};
  const unsigned faces[6][4] = {{3, 0, 3, 2}, {3, 0, 2, 1}, {3, 0, 1, 4}, {3, 1, 2, 4}, {3, 2, 3, 4}, {3, 3, 0, 4}};
  std::string out = "ply\nformat " + format + " 1.0\ncomment made by a scanner\nobj_info units mm\n";
  out += "element vertex 5\nproperty float x\nproperty float y\nproperty float z\nproperty float nx\n"
         "property float ny\nproperty float nz\nproperty uchar red\nproperty uchar green\nproperty uchar blue\n"
         "property uchar alpha\nproperty float s\nproperty float t\nproperty float confidence\n"
         "property int object_id\n";
  out += "element face 6\nproperty list uchar int vertex_indices\nproperty uchar red\nproperty uchar green\n"
         "property uchar blue\nproperty double quality\nproperty list uchar float texcoord\n";
  out += "element edge 2\nproperty int vertex1\nproperty int vertex2\nproperty short crease\nend_header\n";
  const bool ascii = format == "ascii", big = format == "binary_big_endian";
  std::ostringstream os;
  for (int i = 0; i < 5; ++i) {
    const float n[3] = {0, 0, i == 4 ? 1.0f : -1.0f};
    const int rgba[4] = {40 * i, 255 - 40 * i, 7, 200 + i};
    const float st[2] = {0.25f * i, 1 - 0.125f * i}, confidence = 0.5f + 0.0625f * i;
    const int id = 1000 - i;
    if (ascii) {
      os << p[i][0] << ' ' << p[i][1] << ' ' << p[i][2] << ' ' << n[0] << ' ' << n[1] << ' ' << n[2];
      for (int c : rgba) os << ' ' << c;
      os << ' ' << st[0] << ' ' << st[1] << ' ' << confidence << ' ' << id << '\n';
      continue;
    }
    for (float c : p[i]) put_value(out, c, big);
    for (float c : n) put_value(out, c, big);
    for (int c : rgba) put_value(out, static_cast<std::uint8_t>(c), big);
    for (float c : st) put_value(out, c, big);
    put_value(out, confidence, big);
    put_value(out, static_cast<std::int32_t>(id), big);
  }
  for (int f = 0; f < 6; ++f) {
    const double quality = 0.75 * f - 1;
    if (ascii) {
      os << "3 " << faces[f][1] << ' ' << faces[f][2] << ' ' << faces[f][3] << ' ' << 30 * f << " 9 " << 255 - f
         << ' ' << quality << " 2 " << 0.5 * f << " -0.25\n";
      continue;
    }
    put_value(out, std::uint8_t(3), big);
    for (int k = 1; k <= 3; ++k) put_value(out, static_cast<std::int32_t>(faces[f][k]), big);
    for (int c : {30 * f, 9, 255 - f}) put_value(out, static_cast<std::uint8_t>(c), big);
    put_value(out, quality, big);
    put_value(out, std::uint8_t(2), big);
    put_value(out, static_cast<float>(0.5 * f), big);
    put_value(out, -0.25f, big);
  }
  for (int e = 0; e < 2; ++e) {
    if (ascii) {
      os << e << ' ' << 4 << ' ' << -3 * e << '\n';
      continue;
    }
    put_value(out, static_cast<std::int32_t>(e), big);
    put_value(out, std::int32_t(4), big);
    put_value(out, static_cast<std::int16_t>(-3 * e), big);
  }
  return ascii ? out + os.str() : out;
}

Mesh read_ply_mesh(const std::string& bytes) { return build_mesh(read_ply(bytes, "p.ply"), "p.ply"); }

std::string written(const Mesh& mesh, const WriteOptions& options = {}) {
  std::ostringstream os;
  write_mesh(os, MeshFormat::Ply, mesh, options);
  return os.str();
}

// Every column the writer keeps (all but positions and normals) has the same declaration
// and the same values in both sources, and so has the header but for `changed` lines.
void expect_same_kept_columns(const PlySource& a, const PlySource& b) {
  ASSERT_EQ(a.elements.size(), b.elements.size());
  for (std::size_t e = 0; e < a.elements.size(); ++e) {
    const PlyElementData& x = a.elements[e];
    const PlyElementData& y = b.elements[e];
    SCOPED_TRACE(x.name);
    EXPECT_EQ(x.name, y.name);
    EXPECT_EQ(x.count, y.count);
    ASSERT_EQ(x.columns.size(), y.columns.size());
    for (std::size_t k = 0; k < x.columns.size(); ++k) {
      SCOPED_TRACE(x.columns[k].name);
      EXPECT_EQ(x.columns[k].name, y.columns[k].name);
      EXPECT_EQ(x.columns[k].type, y.columns[k].type);
      EXPECT_EQ(x.columns[k].role, y.columns[k].role);
      EXPECT_EQ(x.columns[k].values, y.columns[k].values);
      EXPECT_EQ(x.columns[k].lengths, y.columns[k].lengths);
    }
  }
}

TEST(PlySource, AnUnchangedFileIsWrittenBackByteForByte) {
  for (const char* format : {"ascii", "binary_little_endian", "binary_big_endian"}) {
    SCOPED_TRACE(format);
    const std::string file = pyramid_ply(format);
    const Mesh mesh = read_ply_mesh(file);
    ASSERT_NE(mesh.ply_source(), nullptr);
    EXPECT_EQ(written(mesh), file);
  }
  // A point cloud with normals (no element holds its vertices): the normals are its own.
  const std::string cloud =
      "ply\nformat ascii 1.0\nelement vertex 2\nproperty double x\nproperty double y\nproperty double z\n"
      "property double nx\nproperty double ny\nproperty double nz\nend_header\n0 0 0 0 0 2\n1 0 0 0.5 0 0\n";
  EXPECT_EQ(written(read_ply_mesh(cloud)), cloud);
  // Line ends as the file has them: CRLF, and a lone CR (old Mac and Rhino exports).
  for (const char* end : {"\r\n", "\r"}) {
    std::string file;
    for (char c : pyramid_ply("ascii")) file += c == '\n' ? std::string(end) : std::string(1, c);
    EXPECT_EQ(written(read_ply_mesh(file)), file) << (end[1] ? "CRLF" : "CR");
  }
}

TEST(PlySource, AMovedMeshChangesOnlyItsPositions) {
  for (const char* format : {"ascii", "binary_little_endian", "binary_big_endian"}) {
    SCOPED_TRACE(format);
    const std::string file = pyramid_ply(format);
    Mesh mesh = read_ply_mesh(file);
    for (Eigen::Index i = 0; i < 5; ++i) mesh.positions().col(i) += Eigen::Vector3d(0.1 * i, -0.3, 1.0 / 3);
    const std::string out = written(mesh);
    const Mesh back = read_ply_mesh(out);
    for (Eigen::Index i = 0; i < 5; ++i)
      EXPECT_TRUE(back.positions().col(i) == mesh.positions().col(i).cast<float>().cast<double>()) << i;
    expect_same_kept_columns(*back.ply_source(), *mesh.ply_source());
    EXPECT_EQ(back.ply_source()->header, mesh.ply_source()->header);
    // The encoding can change: the same values in ASCII.
    WriteOptions ascii;
    ascii.encoding = WriteOptions::Encoding::Ascii;
    expect_same_kept_columns(*read_ply_mesh(written(mesh, ascii)).ply_source(), *mesh.ply_source());
  }
}

TEST(PlySource, IntegerCoordinatesAreWrittenAsDoubles) {
  const std::string file =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty short x\nproperty short y\nproperty short z\n"
      "property short weight\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
      "0 0 0 -5\n10 0 0 6\n0 10 0 7\n3 0 1 2\n";
  Mesh mesh = read_ply_mesh(file);
  mesh.positions()(0, 1) = 10.25;
  const std::string out = written(mesh);
  EXPECT_NE(out.find("property double x\nproperty double y\nproperty double z\nproperty short weight\n"),
            std::string::npos)
      << out;
  EXPECT_NE(out.find("10.25 0 0 6\n"), std::string::npos) << out;
}

TEST(PlySource, TristripsAreTrianglesAndWrittenBackAsStrips) {
  // Strip 0 1 2 3, a restart, then 2 3 3 4 5 whose first two triangles are joints.
  const std::string file =
      "ply\nformat ascii 1.0\nelement vertex 6\nproperty float x\nproperty float y\nproperty float z\n"
      "element tristrips 1\nproperty list int int vertex_indices\nend_header\n"
      "0 0 0\n1 0 0\n0 1 0\n1 1 0\n2 1 0\n2 2 0\n10 0 1 2 3 -1 2 3 3 4 5\n";
  const PolygonSoup soup = read_ply(file, "s.ply");
  const std::vector<test::SoupFace> faces = test::soup_faces(soup);
  ASSERT_EQ(faces.size(), 3u);
  EXPECT_EQ(faces[0].vertices, (std::vector<std::uint32_t>{0, 1, 2}));
  EXPECT_EQ(faces[1].vertices, (std::vector<std::uint32_t>{2, 1, 3}));
  EXPECT_EQ(faces[2].vertices, (std::vector<std::uint32_t>{3, 4, 5}));
  const Mesh mesh = read_ply_mesh(file);
  EXPECT_EQ(written(mesh), file);
  EXPECT_EQ(unwritten_data(mesh, MeshFormat::Obj), "");  // the strips' triangles are the mesh's faces
  test::expect_input_error([] { read_ply("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n"
                                         "property float y\nproperty float z\nelement tristrips 1\n"
                                         "property list int int vertex_indices\nend_header\n0 0 0\n3 0 -2 0\n",
                                         "s.ply"); },
                           "s.ply:11: tristrips 0: ", {"vertex index -2 is out of range"});
}

TEST(PlySource, LineEndsAreLfCrLfOrCrAndErrorsCountThemAlike) {
  const std::string lf = pyramid_ply("ascii");
  std::string cr = lf;
  std::replace(cr.begin(), cr.end(), '\n', '\r');
  const PolygonSoup a = read_ply(lf, "p.ply"), b = read_ply(cr, "p.ply");
  EXPECT_EQ(test::soup_faces(a).size(), test::soup_faces(b).size());
  for (std::size_t i = 0; i < a.positions.size(); ++i) EXPECT_TRUE(a.positions[i] == b.positions[i]) << i;
  EXPECT_EQ(test::soup_faces(b)[2].line, test::soup_faces(a)[2].line);
  std::string bad = cr;
  bad.replace(bad.find("\r3 0 1 4 60"), 11, "\r3 0 1 9 60");  // face 2, on line 39
  test::expect_input_error([&] { read_ply(bad, "p.ply"); }, "p.ply:39: face 2: ", {"vertex index 9"});
}

TEST(PlySource, RepeatedPropertyNamesAreKeptAndTheFirstIsTheMeaning) {
  const std::string file =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
      "property float x\nproperty uchar diffuse_red\nproperty uchar diffuse_green\nproperty uchar diffuse_blue\n"
      "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
      "0 0 0 9 255 0 0\n1 0 0 8 0 255 0\n0 1 0 7 0 0 51\n3 0 1 2\n";
  Mesh mesh = read_ply_mesh(file);
  EXPECT_EQ(mesh.positions()(0, 1), 1.0);
  ASSERT_TRUE(mesh.has_colors());
  EXPECT_TRUE(mesh.colors()[2] == Eigen::Vector3f(0, 0, static_cast<float>(51 * (1.0 / 255.0))));
  EXPECT_EQ(written(mesh), file);
  mesh.positions()(0, 1) = 2;
  EXPECT_NE(written(mesh).find("\n2 0 0 8 0 255 0\n"), std::string::npos);
}

TEST(PlySource, PaintedColoursReplaceTheFilesOrAreAdded) {
  const std::string file = pyramid_ply("ascii");
  const Mesh mesh = read_ply_mesh(file);
  WriteOptions paint;
  paint.colors.assign(5, Eigen::Vector3f(1, 0.5f, 0));
  const std::string out = written(mesh, paint);
  EXPECT_EQ(out.substr(0, out.find("end_header")), file.substr(0, file.find("end_header")));
  const Mesh back = read_ply_mesh(out);
  const Eigen::Vector3f orange(1, static_cast<float>(128 * (1.0 / 255.0)), 0);  // 0.5 as a byte, read back
  for (const Eigen::Vector3f& c : back.colors()) EXPECT_TRUE(c == orange);
  EXPECT_EQ(back.ply_source()->elements[0].columns[9].values, mesh.ply_source()->elements[0].columns[9].values);

  const std::string plain = "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty double x\n"
                            "property double y\nproperty double z\nelement face 0\n"
                            "property list uchar int vertex_indices\nend_header\n" + std::string(72, '\0');
  const std::string painted = written(read_ply_mesh(plain), paint);
  EXPECT_NE(painted.find("property double z\nproperty uchar red\nproperty uchar green\nproperty uchar blue\n"),
            std::string::npos);
  EXPECT_TRUE(read_ply_mesh(painted).colors()[1] == orange);
}

TEST(PlySource, WhatOnlyAPlyHoldsIsNamedWhenAWriteDropsIt) {
  Mesh mesh = read_ply_mesh(pyramid_ply("binary_little_endian"));
  EXPECT_EQ(unwritten_data(mesh, MeshFormat::Ply), "");
  const std::string obj = unwritten_data(mesh, MeshFormat::Obj);
  EXPECT_EQ(obj, "the PLY file's vertex alpha, vertex confidence, vertex object_id, face red, face green, face blue, "
                 "face quality, face texcoord, element edge (only a PLY holds them) are not written");
  mesh.mark_topology_changed();
  EXPECT_EQ(mesh.ply_source(), nullptr);
  EXPECT_NE(unwritten_data(mesh, MeshFormat::Ply).find("(the steps changed the connectivity)"), std::string::npos);
  // Without its source, the mesh is written by the plain writer: positions, normals,
  // colours and per-vertex UVs.
  const Mesh plain = read_ply_mesh(written(mesh));
  EXPECT_EQ(plain.ply_source()->carried_only_here(), std::vector<std::string>());
  EXPECT_EQ(plain.uvs(), mesh.uvs());
  EXPECT_EQ(plain.colors(), mesh.colors());
}

TEST(PlyWriter, WritesUvsPerVertexAndNamesThemWhereCornersDiffer) {
  const std::string seamless = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nf 1/1 2/2 3/3\n";
  const Mesh a = build_mesh(read_obj(seamless, "a.obj"), "a.obj");
  EXPECT_EQ(unwritten_data(a, MeshFormat::Ply), "");
  const Mesh back = read_ply_mesh(written(a));
  ASSERT_EQ(back.uvs().size(), 3u);
  EXPECT_TRUE(back.uvs()[1] == Eigen::Vector2d(1, 0));
  const std::string seam = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nvt 1 1\nvt 0.5 0.5\n"
                           "f 1/1 2/2 3/3\nf 2/5 4/4 3/3\n";
  const Mesh b = build_mesh(read_obj(seam, "b.obj"), "b.obj");
  EXPECT_NE(unwritten_data(b, MeshFormat::Ply).find("the UVs (a vertex's corners have different ones"), std::string::npos);
  EXPECT_EQ(written(b).find("property double u"), std::string::npos);
}

// Through the CLI: a real PLY (CGAL's, with normals, colours and an edge element) comes
// back with every value when the lattice does not move it, and an OBJ output names what
// it drops.
TEST(PlySource, TheCliGivesARealFileBackAndWarnsWhatAnObjDrops) {
  const std::string source = test::cgal_mesh("colored_tetra.ply");
  if (source.empty()) GTEST_SKIP() << "CGAL's data set (libcgal-demo) is not installed";
  const std::string dir = test::temp_folder("ply_source_cli");
  const std::string lattice = R"({"op": "lattice", "name": "L", "basis": "bspline", "degree": 3,
                                   "box": {"fit": "aabb", "padding": 0.1}, "cells": [4, 4, 4]})";
  test::write_file(dir + "/s.json", test::script({lattice}));
  std::string err;
  ASSERT_EQ(test::run_tool("run " + source + " " + dir + "/s.json -o " + dir + "/out.ply", nullptr, &err), 0) << err;
  const Mesh in = read_mesh(source), out = read_mesh(dir + "/out.ply");
  expect_same_kept_columns(*out.ply_source(), *in.ply_source());
  EXPECT_TRUE(out.positions() == in.positions());
  EXPECT_EQ(err.find("warning"), std::string::npos) << err;
  ASSERT_EQ(test::run_tool("run " + source + " " + dir + "/s.json -o " + dir + "/out.obj", nullptr, &err), 0) << err;
  EXPECT_NE(err.find("warning: " + dir + "/out.obj: the PLY file's "), std::string::npos) << err;
  EXPECT_NE(err.find("element edge"), std::string::npos) << err;
}

}  // namespace
}  // namespace ffd
