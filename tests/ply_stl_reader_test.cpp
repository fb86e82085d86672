// Our strict PLY and STL readers: against CGAL's readers on real files, binary PLY in both
// endiannesses against ASCII, a seeded mutation loop (never anything but InputError), and
// the error messages, which name the file and the place.
#include <gtest/gtest.h>

#include <CGAL/IO/PLY.h>
#include <CGAL/IO/STL.h>
#include <CGAL/Simple_cartesian.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <random>
#include <sstream>

#include "common/errors.h"
#include "mesh/build_mesh.h"
#include "mesh/mesh_io.h"
#include "mesh/ply_io.h"
#include "mesh/ply_source.h"
#include "mesh/stl_io.h"
#include "test_meshes.h"

namespace ffd {
namespace {

using test::expect_input_error;

using CgalPoint = CGAL::Simple_cartesian<double>::Point_3;


// ---------------------------------------------------------------------------------------
// A small PLY generator: a tetrahedron with normals, colours, texture coordinates and
// properties and an element that the reader skips, in any of the three formats.

struct Tetra {
  std::vector<std::array<float, 3>> p = {{0, 0, 0}, {1, 0, 0}, {0, 1.5f, 0}, {0, 0, -0.25f}};
  std::vector<std::array<double, 3>> n = {{-1, -1, -1}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  std::vector<std::array<int, 3>> rgb = {{255, 0, 0}, {0, 255, 0}, {0, 0, 255}, {10, 20, 30}};
  std::vector<std::array<float, 2>> uv = {{0, 0}, {1, 0}, {0, 1}, {0.5f, 0.5f}};
  std::vector<std::array<unsigned, 3>> faces = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
};

template <typename T>
void put(std::string& out, T v, bool big) {
  char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));
  if (big) std::reverse(b, b + sizeof(T));
  out.append(b, sizeof(T));
}

std::string tetra_ply(const std::string& format, const Tetra& t = {}) {
  std::string out = "ply\nformat " + format + " 1.0\ncomment a generated tetrahedron\n";
  out += "element vertex 4\nproperty float32 x\nproperty float y\nproperty float z\n";
  out += "property double nx\nproperty float64 ny\nproperty double nz\nproperty int16 id\n";
  out += "property uchar red\nproperty uint8 green\nproperty uchar blue\nproperty float u\nproperty float v\n";
  out += "element face 4\nproperty list ushort uint vertex_indices\nproperty char flag\n";
  out += "element edge 1\nproperty list uchar int pair\nproperty double weight\nend_header\n";
  const bool ascii = format == "ascii", big = format == "binary_big_endian";
  std::ostringstream os;
  os.precision(17);
  for (std::size_t i = 0; i < 4; ++i) {
    if (ascii) {
      os << t.p[i][0] << ' ' << t.p[i][1] << ' ' << t.p[i][2] << ' ' << t.n[i][0] << ' ' << t.n[i][1] << ' '
         << t.n[i][2] << " -7 " << t.rgb[i][0] << ' ' << t.rgb[i][1] << ' ' << t.rgb[i][2] << ' ' << t.uv[i][0]
         << ' ' << t.uv[i][1] << '\n';
      continue;
    }
    for (float c : t.p[i]) put(out, c, big);
    for (double c : t.n[i]) put(out, c, big);
    put(out, std::int16_t(-7), big);
    for (int c : t.rgb[i]) put(out, std::uint8_t(c), big);
    for (float c : t.uv[i]) put(out, c, big);
  }
  for (const auto& f : t.faces) {
    if (ascii) {
      os << "3 " << f[0] << ' ' << f[1] << ' ' << f[2] << " -1\n";
      continue;
    }
    put(out, std::uint16_t(3), big);
    for (unsigned v : f) put(out, std::uint32_t(v), big);
    put(out, std::int8_t(-1), big);
  }
  if (ascii) {
    os << "2 0 1 0.5\n";
    return out + os.str();
  }
  put(out, std::uint8_t(2), big);
  put(out, std::int32_t(0), big);
  put(out, std::int32_t(1), big);
  put(out, 0.5, big);
  return out;
}

// A binary STL of the tetrahedron's faces; its header starts with "solid" (the trap).
std::string tetra_binary_stl(const Tetra& t = {}, const std::string& header = "solid but binary") {
  std::string out = header;
  out.resize(80, ' ');
  put(out, std::uint32_t(t.faces.size()), false);
  for (const auto& f : t.faces) {
    for (int k = 0; k < 3; ++k) put(out, 0.0f, false);
    for (unsigned v : f)
      for (float c : t.p[v]) put(out, c, false);
    put(out, std::uint16_t(0), false);
  }
  return out;
}

std::string tetra_ascii_stl(const Tetra& t = {}) {
  std::ostringstream os;
  os.precision(9);
  os << "solid tetra\r\n";
  for (const auto& f : t.faces) {
    os << "  facet normal 0 0 0\r\n    outer loop\r\n";
    for (unsigned v : f) os << "      vertex " << t.p[v][0] << ' ' << t.p[v][1] << ' ' << t.p[v][2] << "\r\n";
    os << "    endloop\r\n  endfacet\r\n";
  }
  os << "endsolid tetra\r\n";
  return os.str();
}

void expect_same_soup(const PolygonSoup& a, const PolygonSoup& b) {
  const std::vector<test::SoupFace> a_faces = test::soup_faces(a);
  const std::vector<test::SoupFace> b_faces = test::soup_faces(b);
  ASSERT_EQ(a.positions.size(), b.positions.size());
  for (std::size_t i = 0; i < a.positions.size(); ++i) EXPECT_TRUE(a.positions[i] == b.positions[i]) << i;
  EXPECT_EQ(a.normals, b.normals);
  EXPECT_EQ(a.colors, b.colors);
  EXPECT_EQ(a.uvs, b.uvs);
  ASSERT_EQ(a_faces.size(), b_faces.size());
  for (std::size_t f = 0; f < a_faces.size(); ++f) {
    EXPECT_EQ(a_faces[f].vertices, b_faces[f].vertices) << f;
    EXPECT_EQ(a_faces[f].normals, b_faces[f].normals) << f;
    EXPECT_EQ(a_faces[f].uvs, b_faces[f].uvs) << f;
  }
}

TEST(PlyReader, ReadsEveryPropertyItKeeps) {
  const Tetra t;
  const PolygonSoup soup = read_ply(tetra_ply("ascii"), "t.ply");
  const std::vector<test::SoupFace> soup_faces = test::soup_faces(soup);
  ASSERT_EQ(soup.positions.size(), 4u);
  for (std::size_t i = 0; i < 4; ++i) {
    EXPECT_TRUE(soup.positions[i] == Eigen::Vector3d(t.p[i][0], t.p[i][1], t.p[i][2])) << i;
    EXPECT_TRUE(soup.normals[i] == Eigen::Vector3d(t.n[i][0], t.n[i][1], t.n[i][2])) << i;
    EXPECT_TRUE(soup.colors[i] == Eigen::Vector3f(t.rgb[i][0] / 255.0f, t.rgb[i][1] / 255.0f, t.rgb[i][2] / 255.0f))
        << i;
    EXPECT_TRUE(soup.uvs[i] == Eigen::Vector2d(t.uv[i][0], t.uv[i][1])) << i;
  }
  ASSERT_EQ(soup_faces.size(), 4u);
  EXPECT_EQ(soup_faces[1].vertices, (std::vector<std::uint32_t>{0, 1, 3}));
  EXPECT_EQ(soup_faces[1].normals, (std::vector<std::int32_t>{0, 1, 3}));
  EXPECT_EQ(soup_faces[1].uvs, (std::vector<std::int32_t>{0, 1, 3}));
  EXPECT_EQ(soup_faces[1].line, 29u);  // the header takes 23 lines, then 4 vertices
}

TEST(PlyReader, ReadsFloatColoursAsTheyAreAndTheOtherTextureNames) {
  const std::string text =
      "ply\r\nformat ascii 1.0\r\nobj_info x\r\nelement vertex 3\r\nproperty double x\r\nproperty double y\r\n"
      "property double z\r\nproperty float red\r\nproperty float green\r\nproperty float blue\r\n"
      "property float alpha\r\nproperty double s\r\nproperty double t\r\nelement face 1\r\n"
      "property list int8 int16 vertex_index\r\nend_header\r\n"
      "0 0 0 0.5 0.25 1 1 0.125 0.75\r\n1 0 0 0 0 0 1 0 0\r\n0 1 0 1 1 1 0 1 1\r\n3 0 1 2\r\n";
  const PolygonSoup soup = read_ply(text, "c.ply");
  const std::vector<test::SoupFace> soup_faces = test::soup_faces(soup);
  ASSERT_EQ(soup.colors.size(), 3u);
  EXPECT_TRUE(soup.colors[0] == Eigen::Vector3f(0.5f, 0.25f, 1.0f));
  ASSERT_EQ(soup.uvs.size(), 3u);
  EXPECT_TRUE(soup.uvs[0] == Eigen::Vector2d(0.125, 0.75));
  EXPECT_TRUE(soup.normals.empty());
  EXPECT_EQ(soup_faces[0].uvs, (std::vector<std::int32_t>{0, 1, 2}));
  EXPECT_EQ(soup_faces[0].line, 20u);
}

TEST(PlyReader, BinaryInBothEndiannessesEqualsAscii) {
  const PolygonSoup ascii = read_ply(tetra_ply("ascii"), "t.ply");
  for (const char* format : {"binary_little_endian", "binary_big_endian"}) {
    SCOPED_TRACE(format);
    expect_same_soup(read_ply(tetra_ply(format), "t.ply"), ascii);
  }
  // CRLF header lines.
  std::string crlf = tetra_ply("binary_big_endian");
  const std::size_t end = crlf.find("end_header\n") + 11;
  std::string head = crlf.substr(0, end), body = crlf.substr(end), fixed;
  for (char c : head) fixed += c == '\n' ? std::string("\r\n") : std::string(1, c);
  expect_same_soup(read_ply(fixed + body, "t.ply"), ascii);
}

// A face element whose only property is its index list, `list COUNT INDEX vertex_indices`
// (binary files read those faces straight from the bytes, read_binary_face): a sheet of
// 5 x 4 vertices with normals and UVs, its faces triangles, quads, one of 20 corners (past
// what the direct read takes) and one that repeats its first vertex.
std::string index_list_ply(const std::string& format, const std::string& count_type, const std::string& index_type) {
  std::vector<std::vector<std::uint32_t>> faces = {{0, 1, 6}, {0, 6, 5}, {1, 2, 7, 6}, {2, 3, 8}, {2, 8, 7}, {3, 4, 9, 8}};
  faces.push_back({5, 6, 11, 10, 5});
  std::vector<std::uint32_t> big;
  for (std::uint32_t v = 10; v < 20; ++v) big.push_back(v);
  for (std::uint32_t v = 19; v >= 10; --v) big.push_back(v);  // 20 corners
  faces.push_back(big);
  std::string out = "ply\nformat " + format + " 1.0\nelement vertex 20\n";
  for (const char* name : {"x", "y", "z", "nx", "ny", "nz", "u", "v"}) out += std::string("property float ") + name + "\n";
  out += "element face " + std::to_string(faces.size()) + "\nproperty list " + count_type + " " + index_type +
         " vertex_indices\nend_header\n";
  const bool ascii = format == "ascii", big_endian = format == "binary_big_endian";
  std::ostringstream os;
  os.precision(9);
  for (int v = 0; v < 20; ++v) {
    const float values[8] = {static_cast<float>(v % 5), static_cast<float>(v / 5), 0.25f * static_cast<float>(v % 3),
                             0, 0, 1, 0.2f * static_cast<float>(v % 5), 0.25f * static_cast<float>(v / 5)};
    for (float x : values) {
      if (ascii) os << x << ' ';
      else put(out, x, big_endian);
    }
    if (ascii) os << '\n';
  }
  for (const auto& f : faces) {
    if (ascii) os << f.size();
    else if (count_type == "uchar") put(out, static_cast<std::uint8_t>(f.size()), big_endian);
    else put(out, static_cast<std::uint16_t>(f.size()), big_endian);
    for (std::uint32_t v : f) {
      if (ascii) os << ' ' << v;
      else if (index_type == "int") put(out, static_cast<std::int32_t>(v), big_endian);
      else put(out, v, big_endian);
    }
    if (ascii) os << '\n';
  }
  return out + os.str();
}

TEST(PlyReader, FacesOfAnIndexListAloneReadAsTheAsciiFileReadsThem) {
  for (const char* count_type : {"uchar", "ushort"})
    for (const char* index_type : {"int", "uint"}) {
      SCOPED_TRACE(std::string(count_type) + " " + index_type);
      const PolygonSoup ascii = read_ply(index_list_ply("ascii", count_type, index_type), "s.ply");
      ASSERT_EQ(test::soup_faces(ascii).size(), 8u);
      for (const char* format : {"binary_little_endian", "binary_big_endian"}) {
        SCOPED_TRACE(format);
        const PolygonSoup binary = read_ply(index_list_ply(format, count_type, index_type), "s.ply");
        expect_same_soup(binary, ascii);
        EXPECT_EQ(binary.elements.corner_normals, ascii.elements.corner_normals);
        EXPECT_EQ(binary.elements.corner_uvs, ascii.elements.corner_uvs);
        // What the PLY writer keeps of the list: each face's length and its entries.
        const PlyColumn& b = binary.ply->elements[1].columns[0];
        const PlyColumn& a = ascii.ply->elements[1].columns[0];
        EXPECT_EQ(b.lengths, a.lengths);
        EXPECT_EQ(b.values, a.values);
      }
    }
}

// ---------------------------------------------------------------------------------------
// CGAL's readers as the oracle on real files.

void expect_ply_as_cgal_reads_it(const std::string& path) {
  SCOPED_TRACE(path);
  std::ifstream is(path, std::ios::binary);
  std::vector<CgalPoint> points;
  std::vector<std::vector<std::size_t>> polygons;
  std::vector<CGAL::IO::Color> colors, face_colors;
  ASSERT_TRUE(CGAL::IO::read_PLY(is, points, polygons,
                                 CGAL::parameters::vertex_color_output_iterator(std::back_inserter(colors))
                                     .face_color_output_iterator(std::back_inserter(face_colors))));
  const PolygonSoup soup = read_ply(test::read_file(path), path);
  const std::vector<test::SoupFace> soup_faces = test::soup_faces(soup);
  ASSERT_EQ(soup.positions.size(), points.size());
  for (std::size_t v = 0; v < points.size(); ++v)
    ASSERT_TRUE(Eigen::Vector3d(points[v].x(), points[v].y(), points[v].z()) == soup.positions[v]) << "vertex " << v;
  ASSERT_EQ(soup_faces.size(), polygons.size());
  for (std::size_t f = 0; f < polygons.size(); ++f)
    ASSERT_EQ(std::vector<std::size_t>(soup_faces[f].vertices.begin(), soup_faces[f].vertices.end()), polygons[f])
        << "face " << f;
  ASSERT_EQ(soup.colors.size(), colors.size());
  for (std::size_t v = 0; v < colors.size(); ++v)
    for (int k = 0; k < 3; ++k) EXPECT_EQ(std::lround(soup.colors[v][k] * 255.0f), colors[v][k]) << "vertex " << v;
}

void expect_stl_as_cgal_reads_it(const std::string& path) {
  SCOPED_TRACE(path);
  std::ifstream is(path, std::ios::binary);
  std::vector<CgalPoint> points;
  std::vector<std::array<std::size_t, 3>> triangles;
  ASSERT_TRUE(CGAL::IO::read_STL(is, points, triangles));
  const PolygonSoup soup = read_stl(test::read_file(path), path);
  const std::vector<test::SoupFace> soup_faces = test::soup_faces(soup);
  ASSERT_EQ(soup.positions.size(), points.size());
  for (std::size_t v = 0; v < points.size(); ++v)
    ASSERT_TRUE(Eigen::Vector3d(points[v].x(), points[v].y(), points[v].z()) == soup.positions[v]) << "vertex " << v;
  ASSERT_EQ(soup_faces.size(), triangles.size());
  for (std::size_t f = 0; f < triangles.size(); ++f)
    ASSERT_EQ(std::vector<std::size_t>(soup_faces[f].vertices.begin(), soup_faces[f].vertices.end()),
              std::vector<std::size_t>(triangles[f].begin(), triangles[f].end()))
        << "triangle " << f;
}

TEST(PlyReader, AgreesWithCgalOnRealFiles) {
  if (test::cgal_meshes().empty()) GTEST_SKIP() << "CGAL's data set (libcgal-demo) is not installed";
  for (const char* name : {"b9.ply", "sphere.ply", "colored_tetra.ply"}) expect_ply_as_cgal_reads_it(test::cgal_mesh(name));
  // colored_tetra.ply also has normals and an edge element, which is skipped.
  const PolygonSoup tetra = read_ply(test::read_file(test::cgal_mesh("colored_tetra.ply")), "colored_tetra.ply");
  EXPECT_EQ(tetra.normals.size(), 4u);
  EXPECT_EQ(tetra.colors.size(), 4u);
}

TEST(PlyReader, AgreesWithCgalOnOurOwnOutput) {
  const std::string dir = test::temp_folder("ply_oracle");
  write_mesh(dir + "/bunny.ply", test::bunny());
  expect_ply_as_cgal_reads_it(dir + "/bunny.ply");
  for (const char* format : {"binary_little_endian", "binary_big_endian", "ascii"}) {
    test::write_file(dir + "/tetra.ply", tetra_ply(format));
    expect_ply_as_cgal_reads_it(dir + "/tetra.ply");
  }
}

TEST(StlReader, AgreesWithCgalOnRealFilesAndOurOwnOutput) {
  const bool cgal = !test::cgal_meshes().empty();
  if (cgal)
    for (const char* name : {"pig.stl", "sphere.stl"}) expect_stl_as_cgal_reads_it(test::cgal_mesh(name));
  const std::string out = test::temp_folder("stl_oracle");
  write_mesh(out + "/bunny.stl", test::bunny());
  expect_stl_as_cgal_reads_it(out + "/bunny.stl");
  test::write_file(out + "/binary.stl", tetra_binary_stl());
  expect_stl_as_cgal_reads_it(out + "/binary.stl");
  test::write_file(out + "/ascii.stl", tetra_ascii_stl());
  expect_stl_as_cgal_reads_it(out + "/ascii.stl");
  if (!cgal) GTEST_SKIP() << "CGAL's data set (libcgal-demo) is not installed";
}

TEST(StlReader, MergesEqualCornersAndReadsTheSolidTrapAsBinary) {
  const PolygonSoup binary = read_stl(tetra_binary_stl(), "t.stl");
  const std::vector<test::SoupFace> binary_faces = test::soup_faces(binary);
  const PolygonSoup ascii = read_stl(tetra_ascii_stl(), "t.stl");
  const std::vector<test::SoupFace> ascii_faces = test::soup_faces(ascii);
  EXPECT_EQ(binary.positions.size(), 4u);
  // First seen first: faces {0,2,1}, {0,1,3}, ... number p0, p2, p1, p3.
  EXPECT_EQ(binary_faces[0].vertices, (std::vector<std::uint32_t>{0, 1, 2}));
  EXPECT_EQ(binary_faces[3].vertices, (std::vector<std::uint32_t>{2, 1, 3}));
  expect_same_soup(binary, ascii);
  EXPECT_EQ(ascii_faces[1].line, 9u);
  // -0 and 0 are one point, as in CGAL's map of points.
  Tetra t;
  t.p[3] = {-0.0f, 0.0f, -0.25f};
  t.p.push_back({0.0f, -0.0f, -0.25f});
  t.faces.push_back({4, 1, 2});
  const PolygonSoup zeros = read_stl(tetra_binary_stl(t), "t.stl");
  const std::vector<test::SoupFace> zeros_faces = test::soup_faces(zeros);
  EXPECT_EQ(zeros.positions.size(), 4u);
  EXPECT_EQ(zeros_faces[4].vertices, (std::vector<std::uint32_t>{3, 2, 1}));
  const std::string path = test::temp_folder("stl_zeros") + "/zeros.stl";
  test::write_file(path, tetra_binary_stl(t));
  expect_stl_as_cgal_reads_it(path);
}

// ---------------------------------------------------------------------------------------
// Mutations: whatever the bytes, a soup or an InputError.

struct MutationTally {
  std::size_t runs = 0, accepted = 0, refused = 0;
};

std::string mutate(std::string s, std::mt19937_64& rng) {
  const auto pick = [&](std::size_t n) { return n == 0 ? std::size_t(0) : std::size_t(rng() % n); };
  switch (rng() % 6) {
    case 0:  // flip a few bytes
      for (std::size_t k = 0, n = 1 + pick(4); k < n && !s.empty(); ++k) s[pick(s.size())] ^= char(1 + pick(255));
      break;
    case 1:  // truncate
      s.resize(pick(s.size() + 1));
      break;
    case 2: {  // duplicate a range
      const std::size_t a = pick(s.size() + 1), n = pick(std::min<std::size_t>(64, s.size() - a + 1));
      s.insert(pick(s.size() + 1), s.substr(a, n));
      break;
    }
    case 3: {  // delete a range
      const std::size_t a = pick(s.size() + 1);
      s.erase(a, pick(65));
      break;
    }
    case 4: {  // a huge number in place of a header number
      std::vector<std::size_t> digits;
      for (std::size_t i = 0; i < std::min<std::size_t>(s.size(), 600); ++i)
        if (s[i] >= '0' && s[i] <= '9') digits.push_back(i);
      if (digits.empty()) break;
      const std::size_t at = digits[pick(digits.size())];
      const char* huge[] = {"4294967295", "18446744073709551615", "99999999999999999999999", "2147483648", "-1"};
      s.replace(at, 1, huge[pick(5)]);
      break;
    }
    default: {  // a huge binary count (a list length, the STL triangle count)
      if (s.size() < 4) break;
      const std::size_t at = s.size() >= 84 && rng() % 2 ? 80 : pick(s.size() - 3);
      const std::uint32_t values[] = {0xffffffffu, 0x7fffffffu, 0x10000u, 255u};
      std::memcpy(&s[at], &values[pick(4)], 4);
      break;
    }
  }
  return s;
}

void run_mutations(const std::string& seed_file, const std::function<PolygonSoup(const std::string&)>& read,
                   std::uint64_t seed, int count, MutationTally& tally) {
  std::mt19937_64 rng(seed);
  for (int i = 0; i < count; ++i) {
    std::string bytes = mutate(seed_file, rng);
    if (rng() % 4 == 0) bytes = mutate(bytes, rng);
    ++tally.runs;
    try {
      const PolygonSoup soup = read(bytes);
      build_mesh(soup, "m");  // and whatever it holds, build_mesh only refuses
      ++tally.accepted;
    } catch (const InputError&) {
      ++tally.refused;
    } catch (const std::exception& e) {
      ADD_FAILURE() << "mutation " << i << " of seed " << seed << ": not an InputError: " << e.what();
    }
  }
}

TEST(ReaderMutations, EveryMutationIsReadOrRefusedWithInputError) {
  const auto start = std::chrono::steady_clock::now();
  MutationTally tally;
  const auto ply = [](const std::string& b) { return read_ply(b, "m.ply"); };
  const auto stl = [](const std::string& b) { return read_stl(b, "m.stl"); };
  const int n = 2000;
  run_mutations(tetra_ply("ascii"), ply, 1, n, tally);
  run_mutations(tetra_ply("binary_little_endian"), ply, 2, n, tally);
  run_mutations(tetra_ply("binary_big_endian"), ply, 3, n, tally);
  run_mutations(tetra_ascii_stl(), stl, 4, n, tally);
  run_mutations(tetra_binary_stl(), stl, 5, n, tally);
  run_mutations(tetra_binary_stl({}, "binary, no solid"), stl, 6, n, tally);
  // Faces of an index list alone, which binary files read straight from the bytes.
  run_mutations(index_list_ply("binary_little_endian", "uchar", "int"), ply, 9, n / 4, tally);
  run_mutations(index_list_ply("binary_big_endian", "ushort", "uint"), ply, 10, n / 4, tally);
  // And a few on ffdtool's own output of the bunny, a real-size file.
  const std::string dir = test::temp_folder("mutations");
  write_mesh(dir + "/bunny.ply", test::bunny());
  write_mesh(dir + "/bunny.stl", test::bunny());
  run_mutations(test::read_file(dir + "/bunny.ply"), ply, 7, 100, tally);
  run_mutations(test::read_file(dir + "/bunny.stl"), stl, 8, 100, tally);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("mutations: %zu runs, %zu read, %zu refused, %.2f s\n", tally.runs, tally.accepted, tally.refused,
              seconds);
  EXPECT_EQ(tally.runs, 6u * n + 2u * (n / 4) + 200);
  EXPECT_GT(tally.refused, tally.runs / 4);  // the mutations do break files
  EXPECT_LT(seconds, 10.0);
}

// ---------------------------------------------------------------------------------------
// Errors: one line, the file and the place.

std::string header(const std::string& format, const std::string& vertices, const std::string& faces) {
  return "ply\nformat " + format + " 1.0\nelement vertex " + vertices +
         "\nproperty float x\nproperty float y\nproperty float z\nelement face " + faces +
         "\nproperty list uchar int vertex_indices\nend_header\n";
}

std::string binary_triangle(float bad = 0, int index = 2, std::uint8_t length = 3) {
  std::string out = header("binary_little_endian", "3", "1");
  const float p[9] = {0, 0, 0, 1, 0, 0, 0, 1, bad};
  for (float c : p) put(out, c, false);
  put(out, length, false);
  for (int v : {0, 1, index}) put(out, std::int32_t(v), false);
  return out;
}

TEST(PlyReader, ErrorsNameTheFileAndThePlace) {
  const auto read = [](const std::string& bytes) { return [bytes] { read_ply(bytes, "f.ply"); }; };
  expect_input_error(read(""), "f.ply: ", {"empty"});
  expect_input_error(read("plx\n"), "f.ply:1: ", {"not a PLY file"});
  expect_input_error(read("ply\nformat ascii 1.0\nelement vertex 1\n"), "f.ply: ", {"end_header"});
  expect_input_error(read("ply\nformat ascii 2.0\n"), "f.ply:2: ", {"format"});
  expect_input_error(read("ply\nformat ascii 1.0\nproperty float x\nend_header\n"), "f.ply:3: ", {"before any element"});
  expect_input_error(read("ply\nformat ascii 1.0\nelement vertex 1\nproperty quad x\n"), "f.ply:4: ", {"'quad'"});
  expect_input_error(read(header("ascii", "0", "0")), "f.ply: the file has no vertex");
  expect_input_error(read(header("ascii", "18446744073709551616", "0")), "f.ply:3: ", {"element NAME COUNT"});
  expect_input_error(read(header("ascii", "-3", "0")), "f.ply:3: ", {"count of 0 or more"});
  expect_input_error(read("ply\nformat ascii 1.0\nelement face 0\nproperty list uchar int vertex_indices\nend_header\n"),
                     "f.ply: the file has no vertex");
  // Huge counts against a small file.
  expect_input_error(read(header("binary_little_endian", "4000000000", "0") + "abc"), "f.ply:3: ",
                     {"element vertex promises 4000000000 items", "3 bytes are left", "at least 12"});
  expect_input_error(read(header("ascii", "3", "99999999999") + "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"), "f.ply:7: ",
                     {"element face promises 99999999999"});
  expect_input_error(read(binary_triangle(0, 2, 250)), "f.ply: face 0: ", {"list vertex_indices promises 250 items"});
  // Indices, coordinates, truncation.
  expect_input_error(read(binary_triangle(0, 99)), "f.ply: face 0: ",
                     {"vertex index 99 is out of range (the file has 3 vertices)"});
  expect_input_error(read(binary_triangle(0, 2, 2).substr(0, binary_triangle().size() - 4)), "f.ply: face 0: ",
                     {"a face needs at least 3 vertices, found 2"});
  expect_input_error(read(binary_triangle(0, -1)), "f.ply: face 0: ", {"vertex index -1 is out of range"});
  expect_input_error(read(header("ascii", "3", "1") + "0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n"), "f.ply:13: face 0: ",
                     {"vertex index 3 is out of range"});
  expect_input_error(read(binary_triangle(std::numeric_limits<float>::quiet_NaN())), "f.ply: vertex 2: ",
                     {"z is not finite (nan)"});
  expect_input_error(read(binary_triangle(std::numeric_limits<float>::infinity())), "f.ply: vertex 2: ",
                     {"z is not finite (inf)"});
  expect_input_error(read(header("ascii", "3", "1") + "0 0 0\n1 nan 0\n0 1 0\n3 0 1 2\n"), "f.ply:11: vertex 1: ",
                     {"y is not finite"});
  expect_input_error(read(header("ascii", "3", "1") + "0 0 0\n1 1e999 0\n0 1 0\n3 0 1 2\n"), "f.ply:11: vertex 1: ",
                     {"'1e999' is not a finite number"});
  expect_input_error(read(header("ascii", "3", "1") + "0 0 0\n1 0 0\n0 1 0\n3 0 1\n"), "f.ply:13: face 0: ",
                     {"the file ends inside it (expected vertex_indices)"});
  expect_input_error(read(header("ascii", "3", "1") + "0 0 0\n1 0 0\n0 1 0\n3 0 1 2 7\n"), "f.ply:13: ",
                     {"unexpected data after the last element"});
  std::string cut = binary_triangle();
  cut.resize(cut.size() - 2);
  expect_input_error(read(cut), "f.ply: face 0: ", {"list vertex_indices promises 3 items", "10 bytes left"});
  cut = header("binary_little_endian", "2", "0");
  cut.insert(cut.find("element face"), "property list uchar float extra\n");
  for (int k = 0; k < 3; ++k) put(cut, 0.0f, false);
  put(cut, std::uint8_t(3), false);  // vertex 0 takes 25 bytes, vertex 1 is cut short
  cut += std::string(12 + 2, '\0');
  expect_input_error(read(cut), "f.ply: vertex 1: ", {"the file ends inside it (expected x)"});
  // Padding after a binary file's last element is read past, as exporters pad.
  EXPECT_EQ(read_ply(binary_triangle() + "xy", "f.ply").elements.size(), read_ply(binary_triangle(), "f.ply").elements.size());
}

TEST(StlReader, ErrorsNameTheFileAndThePlace) {
  const auto read = [](const std::string& bytes) { return [bytes] { read_stl(bytes, "f.stl"); }; };
  expect_input_error(read(""), "f.stl: the file is empty");
  std::string binary = tetra_binary_stl({}, "binary");
  binary.resize(84 + 50 * 3);
  expect_input_error(read(binary), "f.stl: ",
                     {"count of 4 triangles needs 284 bytes", "the file has 234"});
  std::string solid = tetra_binary_stl();
  solid += "x";
  expect_input_error(read(solid), "f.stl: ", {"count of 4 triangles", "the file has 285"});
  expect_input_error(read("abc"), "f.stl: ", {"3 bytes", "too short"});
  expect_input_error(read(tetra_binary_stl({}, "empty").substr(0, 80) + std::string(4, '\0')),
                     "f.stl: the file has no vertex");
  Tetra t;
  t.p[2][1] = std::numeric_limits<float>::infinity();
  expect_input_error(read(tetra_binary_stl(t, "x")), "f.stl: triangle 0: ", {"corner 1", "non-finite", "inf"});
  std::string text = tetra_ascii_stl();
  expect_input_error(read(text.substr(0, text.size() - 17)), "f.stl:", {"ends before 'endsolid'"});
  std::string nan = text;
  nan.replace(nan.find("vertex 0 1.5 0"), 14, "vertex 0 nan 0");
  expect_input_error(read(nan), "f.stl:5: triangle 0: ", {"coordinate 'nan' is not a finite number"});
  std::string noloop = text;
  noloop.replace(noloop.find("outer loop"), 10, "outer lap ");
  expect_input_error(read(noloop), "f.stl:3: ", {"expected 'loop', found 'lap'"});
  expect_input_error(read("solid x\nendsolid x\n"), "f.stl: the file has no vertex");
}

}  // namespace
}  // namespace ffd
