// Mesh I/O: exact round trips (OBJ, OFF), agreement with independent readers
// (tinyobjloader, CGAL), strict rejection of bad input with file and line, attributes
// (UVs, file normals) through a deformation.
#include <gtest/gtest.h>

#include <CGAL/IO/OFF.h>
#include <CGAL/IO/PLY.h>
#include <CGAL/IO/STL.h>
#include <CGAL/Simple_cartesian.h>

#include <tiny_obj_loader.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <numeric>
#include <random>
#include <sstream>

#include "common/errors.h"
#include "common/file_bytes.h"
#include "common/numbers.h"
#include "fuzz/reader_paths.h"
#include "mesh/build_mesh.h"
#include "mesh/halfedge_view.h"
#include "mesh/mesh_io.h"
#include "mesh/obj_io.h"
#include "mesh/obj_source.h"
#include "mesh/off_io.h"
#include "mesh/ply_io.h"
#include "mesh/text_lines.h"
#include "script/runner.h"
#include "test_meshes.h"
#include "warp/bspline_lattice.h"
#include "warp/warp_stack.h"

namespace ffd {
namespace {

using test::expect_input_error;

using CgalPoint = CGAL::Simple_cartesian<double>::Point_3;

// ---------------------------------------------------------------------------------------
// Helpers

// 17 significant digits: a double written the way other tools write them.
std::string digits17(double x) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", x);
  return buf;
}

std::string write_to_string(const Mesh& mesh, MeshFormat format, const WriteOptions& options = {}) {
  std::ostringstream os;
  write_mesh(os, format, mesh, options);
  return os.str();
}

// Connectivity of a polygon mesh with triangles, quads and pentagons over an n × n grid of
// vertices, plus n extra vertices on the bottom edge that turn the first row into pentagons.
// Vertex (i, j) is j * (n + 1) + i; bottom midpoint i is (n + 1)^2 + i. All faces CCW.
std::vector<std::vector<std::uint32_t>> polygon_faces(int n) {
  const auto id = [n](int i, int j) { return static_cast<std::uint32_t>(j * (n + 1) + i); };
  const auto mid = [n](int i) { return static_cast<std::uint32_t>((n + 1) * (n + 1) + i); };
  std::vector<std::vector<std::uint32_t>> faces;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const std::uint32_t a = id(i, j), b = id(i + 1, j), c = id(i + 1, j + 1), d = id(i, j + 1);
      if (j == 0) {
        faces.push_back({a, mid(i), b, c, d});  // pentagon
      } else if (j % 3 == 2) {
        faces.push_back({a, b, c});
        faces.push_back({a, c, d});
      } else {
        // Quads; rotate the first vertex so that it is not always the smallest index.
        std::vector<std::uint32_t> q = {a, b, c, d};
        std::rotate(q.begin(), q.begin() + (i % 4), q.end());
        faces.push_back(q);
      }
    }
  return faces;
}

int polygon_vertex_count(int n) { return (n + 1) * (n + 1) + n; }

// Random positions with full 17-digit precision near the grid (any magnitude is fine
// for I/O; a few extreme ones are mixed in).
std::vector<Eigen::Vector3d> random_positions(int n, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> jitter(-0.3, 0.3), z(-1, 1);
  std::vector<Eigen::Vector3d> p;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) p.emplace_back(i + jitter(rng), j + jitter(rng), z(rng));
  for (int i = 0; i < n; ++i) p.emplace_back(i + 0.5 + jitter(rng) * 0.1, -0.2 + jitter(rng) * 0.1, z(rng));
  // Extreme magnitudes and awkward values; re-read through %.17g like a foreign writer.
  p[1].z() = 1e-300 * (1 + z(rng));
  p[2].z() = -123456789.12345678;
  p[3].z() = 0.1 + 0.2;
  p[4].x() = 4.9406564584124654e-324 * 7;  // subnormal
  for (auto& v : p)
    for (int k = 0; k < 3; ++k) v[k] = std::strtod(digits17(v[k]).c_str(), nullptr);
  return p;
}

void expect_same_soup(const PolygonSoup& a, const PolygonSoup& b, const std::string& what) {
  const std::vector<test::SoupFace> a_faces = test::soup_faces(a);
  const std::vector<test::SoupFace> b_faces = test::soup_faces(b);
  SCOPED_TRACE(what);
  ASSERT_EQ(a.positions.size(), b.positions.size());
  for (std::size_t i = 0; i < a.positions.size(); ++i)
    ASSERT_TRUE(a.positions[i] == b.positions[i]) << "vertex " << i << ": " << a.positions[i].transpose()
                                                  << " vs " << b.positions[i].transpose();
  ASSERT_EQ(a.uvs.size(), b.uvs.size());
  for (std::size_t i = 0; i < a.uvs.size(); ++i) ASSERT_TRUE(a.uvs[i] == b.uvs[i]) << "vt " << i;
  ASSERT_EQ(a.normals.size(), b.normals.size());
  for (std::size_t i = 0; i < a.normals.size(); ++i) ASSERT_TRUE(a.normals[i] == b.normals[i]) << "vn " << i;
  ASSERT_EQ(a.colors.size(), b.colors.size());
  for (std::size_t i = 0; i < a.colors.size(); ++i) ASSERT_TRUE(a.colors[i] == b.colors[i]) << "colour " << i;
  ASSERT_EQ(a_faces.size(), b_faces.size());
  for (std::size_t f = 0; f < a_faces.size(); ++f) {
    ASSERT_EQ(a_faces[f].vertices, b_faces[f].vertices) << "face " << f;
    ASSERT_EQ(a_faces[f].uvs, b_faces[f].uvs) << "face " << f;
    ASSERT_EQ(a_faces[f].normals, b_faces[f].normals) << "face " << f;
    const ObjState sa = a_faces[f].group >= 0 ? a.groups[a_faces[f].group] : ObjState{};
    const ObjState sb = b_faces[f].group >= 0 ? b.groups[b_faces[f].group] : ObjState{};
    ASSERT_TRUE(sa == sb) << "face " << f << ": o/g/usemtl/s '" << sa.object << "' '" << sa.group << "' '"
                          << sa.material << "' '" << sa.smoothing << "' vs '" << sb.object << "' '" << sb.group
                          << "' '" << sb.material << "' '" << sb.smoothing << "'";
  }
  EXPECT_EQ(a.header, b.header);
}


Mesh obj_mesh(const std::string& text, const std::string& file = "x.obj") {
  return build_mesh(read_obj(text, file), file);
}

// ---------------------------------------------------------------------------------------
// OBJ round trip

struct ObjModel {
  std::string text;
  PolygonSoup soup;  // what the text means
};

// An OBJ file with everything the format carries for ffdtool: mtllib, o/g/usemtl/s,
// 17-digit positions, UVs, normals, per-corner indices in every corner syntax, polygons.
ObjModel random_obj(int n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  ObjModel m;
  PolygonSoup& s = m.soup;
  s.positions = random_positions(n, rng);
  std::uniform_real_distribution<double> unit(-1, 1);
  const int nv = static_cast<int>(s.positions.size());
  for (int i = 0; i < nv + 7; ++i)
    s.uvs.emplace_back(std::strtod(digits17(unit(rng) * 0.5 + 0.5).c_str(), nullptr),
                       std::strtod(digits17(unit(rng) * 0.5 + 0.5).c_str(), nullptr));
  for (int i = 0; i < nv / 2; ++i) {
    Eigen::Vector3d v(unit(rng), unit(rng), unit(rng));
    v.normalize();
    for (int k = 0; k < 3; ++k) v[k] = std::strtod(digits17(v[k]).c_str(), nullptr);
    s.normals.push_back(v);
  }
  s.header = {"mtllib scene.mtl other.mtl"};

  std::ostringstream os;
  os << "# a test file\n" << s.header[0] << "\n";
  for (const auto& p : s.positions) os << "v " << digits17(p.x()) << " " << digits17(p.y()) << "\t" << digits17(p.z()) << "\n";
  os << "\n";
  for (const auto& t : s.uvs) os << "vt " << digits17(t.x()) << " " << digits17(t.y()) << "\n";
  for (const auto& v : s.normals) os << "vn " << digits17(v.x()) << " " << digits17(v.y()) << " " << digits17(v.z()) << "\n";

  const auto faces = polygon_faces(n);
  std::uniform_int_distribution<int> pick_uv(0, static_cast<int>(s.uvs.size()) - 1),
      pick_vn(0, static_cast<int>(s.normals.size()) - 1);
  ObjState state;
  const auto set_state = [&](const std::string& key, const std::string& value, std::string ObjState::*slot) {
    os << key << (value.empty() ? "" : " " + value) << "\n";
    state.*slot = value;
    s.groups.push_back(state);
  };
  for (std::size_t f = 0; f < faces.size(); ++f) {
    if (f == 0) {
      os << "o part_a\ng left arm\nusemtl red\n";
      state.object = "part_a";
      state.group = "left arm";
      state.material = "red";
      set_state("s", "1", &ObjState::smoothing);
    } else if (f == 5) {
      set_state("usemtl", "blue", &ObjState::material);
    } else if (f == 9) {
      os << "g right_arm\n";
      state.group = "right_arm";
      set_state("s", "off", &ObjState::smoothing);
    } else if (f == 17) {
      set_state("o", "part_b", &ObjState::object);
    } else if (f == 30) {
      set_state("usemtl", "red", &ObjState::material);  // back to an earlier state
    }
    test::SoupFace face{faces[f], {}, {}};
    face.group = static_cast<std::int32_t>(s.groups.size()) - 1;
    const int syntax = static_cast<int>(f % 4);  // v, v/t, v//n, v/t/n
    os << "f";
    for (std::uint32_t v : faces[f]) {
      // Mix 1-based and negative (relative) indices for vertices.
      const bool relative = (f % 7) == 3;
      os << " " << (relative ? std::to_string(static_cast<int>(v) - nv) : std::to_string(v + 1));
      if (syntax == 1 || syntax == 3) {
        face.uvs.push_back(pick_uv(rng));
        os << "/" << face.uvs.back() + 1;
      }
      if (syntax == 2) os << "/";
      if (syntax >= 2) {
        face.normals.push_back(pick_vn(rng));
        os << "/" << face.normals.back() + 1;
      }
    }
    os << (f == 11 ? "  # trailing comment\n" : "\n");
    test::add_face(s, face.vertices, face.uvs, face.normals, face.group);
  }
  m.text = os.str();
  return m;
}

TEST(NewlineFinder, FindsWhatFindFinds) {
  // Texts of every length to 80 around the finder's 16-byte blocks, sparse to dense in
  // '\n', with CRLF and NUL bytes; every start position, as LineScanner's calls go forward.
  std::mt19937 rng(11);
  for (std::size_t size = 0; size <= 80; ++size)
    for (const int per_hundred : {0, 3, 30, 90}) {
      std::string text(size, 'x');
      for (char& c : text) {
        const int roll = static_cast<int>(rng() % 100);
        c = roll < per_hundred ? '\n' : roll == 99 ? '\0' : roll == 98 ? '\r' : 'v';
      }
      const std::string_view view(text);
      for (std::size_t from = 0; from <= size + 1; ++from) {
        NewlineFinder finder(view);
        for (std::size_t at = from; at <= size + 1; at += 1 + at % 7) {
          const std::size_t expected = std::min(view.find('\n', at), size);
          ASSERT_EQ(finder.next(at), expected) << "size " << size << ", from " << at;
        }
      }
      LineScanner lines(view);
      std::string_view line;
      std::size_t count = 0, pos = 0;
      while (lines.next(line)) {
        const std::size_t end = std::min(view.find('\n', pos), size);
        std::string_view expected = view.substr(pos, end - pos);
        if (!expected.empty() && expected.back() == '\r') expected.remove_suffix(1);
        ASSERT_EQ(line, expected);
        pos = end + 1;
        EXPECT_EQ(lines.number(), ++count);
      }
      EXPECT_GE(pos, size);
    }
}

TEST(CountKeyedLines, CountsWhatAWalkOverTheLinesCounts) {
  // Texts of every length to 80 around the 16-byte blocks and their 18-byte reach, from
  // the letters, blanks and newlines a keyed line is made of, dense enough that keyed lines
  // start in every lane, at the text's start and in the last bytes.
  std::mt19937 rng(12);
  const char alphabet[] = {'v', 'f', ' ', '\t', '\n', '\n', 'x', '1'};
  for (std::size_t size = 0; size <= 80; ++size)
    for (int trial = 0; trial < 40; ++trial) {
      std::string text(size, ' ');
      for (char& c : text) c = alphabet[rng() % sizeof alphabet];
      std::size_t v = 0, f = 0;
      for (std::size_t start = 0; start < size;) {  // the lines, one by one
        if (start + 1 < size && (text[start + 1] == ' ' || text[start + 1] == '\t'))
          v += text[start] == 'v', f += text[start] == 'f';
        const std::size_t end = text.find('\n', start);
        if (end == std::string::npos) break;
        start = end + 1;
      }
      const auto counts = count_keyed_lines(text, 'v', 'f');
      ASSERT_EQ(counts[0], v) << "'" << text << "'";
      ASSERT_EQ(counts[1], f) << "'" << text << "'";
    }
}

TEST(Decimal, ReadsWhatFromCharsReads) {
  // Signs, leading zeros, 0 to 25 digits (past the 18 of the plain loop and past the
  // range of long long), and what follows, with more digits after a stop: the value, the
  // end and the error must agree.
  std::mt19937 rng(13);
  std::vector<std::string> texts = {"", "-", "+1", "-0", "0", "00012", "9223372036854775807", "9223372036854775808",
                                    "-9223372036854775808", "-9223372036854775809", "999999999999999999",
                                    "1000000000000000000", "123/4", "12 3", "1e3", "\xff" "1"};
  for (int trial = 0; trial < 20000; ++trial) {
    std::string t = rng() % 4 == 0 ? "-" : "";
    const std::size_t digits = rng() % 26;
    for (std::size_t k = 0; k < digits; ++k) t += static_cast<char>('0' + (k == 0 && rng() % 2 ? 9 : rng() % 10));
    if (rng() % 2) t += " /x-:?"[rng() % 6];  // ":" and "?" follow "9" in ASCII
    if (rng() % 3 == 0) t += std::to_string(rng() % 100000) + " 123456789";  // more after a stop
    texts.push_back(t);
  }
  for (const std::string& t : texts) {
    long long expected = 77, got = 77;
    const auto want = std::from_chars(t.data(), t.data() + t.size(), expected);
    const auto have = decimal(t.data(), t.data() + t.size(), got);
    ASSERT_EQ(have.ec, want.ec) << "'" << t << "'";
    ASSERT_EQ(have.ptr, want.ptr) << "'" << t << "'";
    ASSERT_EQ(got, expected) << "'" << t << "'";
  }
}

TEST(FileBytes, ReleasedPagesReadBackTheSameBytes) {
  // read_mesh gives a parsed file's pages back before building the mesh (peak memory:
  // the 1M-vertex sphere job 257 -> 185 bytes per vertex); the bytes stay readable.
  const std::string path = test::temp_folder("file_bytes") + "/big.obj";
  std::string text;
  for (int i = 0; i < 200000; ++i) text += "v " + std::to_string(i) + " 0.5 1e-3\n";  // several MB: many pages
  {
    std::ofstream out(path, std::ios::binary);
    out << text;
  }
  const FileBytes bytes = read_file_bytes(path);
  ASSERT_EQ(bytes.view(), text);
  bytes.release_pages();
  EXPECT_EQ(bytes.view(), text);
  FileBytes owned(std::string("not mapped"));
  owned.release_pages();
  EXPECT_EQ(owned.view(), "not mapped");
  const Mesh mesh = read_mesh(path);  // the reader that releases them
  EXPECT_EQ(mesh.num_vertices(), 200000u);
  EXPECT_EQ(mesh.positions()(0, 199999), 199999.0);
}

TEST(ObjIo, ReadsEveryStatementExactly) {
  const ObjModel model = random_obj(8, 1);
  const PolygonSoup soup = read_obj(model.text, "model.obj");
  const std::vector<test::SoupFace> soup_faces = test::soup_faces(soup);
  expect_same_soup(model.soup, soup, "file as written vs as read");
  // Polygons of every kind are kept as they are.
  std::map<std::size_t, std::size_t> degrees;
  for (const test::SoupFace& f : soup_faces) ++degrees[f.vertices.size()];
  EXPECT_GT(degrees[3], 0u);
  EXPECT_GT(degrees[4], 0u);
  EXPECT_GT(degrees[5], 0u);
}

// Runs a reader's fast-against-general check on each text: a difference fails the test;
// `read` and `refused` count the texts both paths read, and both refused alike.
void check_paths_agree_on(const std::vector<std::string>& texts, void (*check)(std::string_view),
                          std::size_t& read, std::size_t& refused) {
  for (const std::string& text : texts) {
    try {
      check(text);
      ++read;
    } catch (const InputError&) {
      ++refused;
    } catch (const std::logic_error& e) {
      ADD_FAILURE() << e.what() << " on:\n" << text.substr(0, 400);
    }
  }
}

// read_obj parses the common `v` and `f` lines in place and hands anything else to the
// general tokenizing reader: both must read the same soup, or fail with the same message.
TEST(ObjIo, FastPathReadsWhatTheGeneralPathReads) {
  std::vector<std::string> texts = {test::read_file(test::data("bunny.obj"))};
  for (std::uint64_t seed : {1, 2, 3}) texts.push_back(random_obj(10, seed).text);
  const std::string head = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\n";
  for (const char* line :
       {"f 1 2 3", "f -3 -2 -1", "f 1/1 2/1 3/1", "f 1//1 2//1 3//1", "f 1/1/1 2/1/1 3/1/1", "f 1/ 2/ 3/",
        "f 1// 2// 3//", "f 1/1/ 2 3", "f +1 2 3", "f 1 2 3 # c", "f 1 2 3#c", "f\t1\t2\t3\t", "f 1 2", "f 1 2 4",
        "f 0 1 2", "f 1 2 3/2", "f 1/1/1/1 2 3", "f 1 2 3 x", "f 01 2 3", "f 1 2 99999999999999999999",
        "f 1 2 3 1 2 3 1 2", "f 1 2 3 1 2 3 1 2 3", "f 1 2/1 3", "f 1 2 3 1 2 3 1 2/1", "f -1 -2 -3 -4",
        "v 1 2 3 4", "v 1 2", "v 1 2 3 1", "v +1 2 3", "v 1e400 0 0", "v nan 0 0", "v inf 0 0", "v -0 0x1 0",
        "v 1. .5 -.5e-3", "v 1 2 3 0.5 0.5 0.5", "v\t1\t2\t3\t", "  v 1 2 3", "vv 1 2 3", "v 1 2 3\r"}) {
    texts.push_back(head + line + "\nf 1 2 3\n");
    texts.push_back(head + "g part\n" + line + "\nf 1 2 3\nv 1 1 1 0.2 0.3 0.4\n" + line + "\n");
  }
  std::size_t read = 0, refused = 0;
  check_paths_agree_on(texts, fuzz::check_obj_paths_agree, read, refused);
  EXPECT_GT(read, 10u);
  EXPECT_GT(refused, 10u);
}

// read_off parses plain vertex and face lines in place and hands anything else to the
// general reader: both must read the same soup, or fail with the same message.
TEST(OffIo, FastPathReadsWhatTheGeneralPathReads) {
  std::vector<std::string> texts = {write_to_string(test::bunny(), MeshFormat::Off)};
  for (const char* vertex : {"1 0 0", "1 0 0 # c", "1 0 0#c", "+1 0 0", "1 0", "1 0 0 0", "1e400 0 0", "nan 0 0",
                             "\t1\t0\t0\t", "", "# only a comment", "1. .5 -.5e-3", "1 0 0\r"})
    for (const char* face : {"3 0 1 2", "3 0 1 3", "3 0 1 -1", "3 0 1", "3 0 1 2 4", "3 0 1 2 255 0 0",
                             "3 0 1 2 0.5 0.5 0.5 1", "3 0 1 2 5 6", "3 0 1 2 x", "+3 0 1 2", "2 0 1", "4 0 1 2 3", "3 0 1 2 # c", "",
                             "99999999999999999999 0 1 2", "3 0 1 02"}) {
      for (const char* keyword : {"OFF", "COFF", "NOFF", "STOFF"}) {
        const std::string k = keyword;
        const std::string extra = k == "COFF" ? " 1 0 0" : k == "NOFF" ? " 0 0 1" : k == "STOFF" ? " 0 0" : "";
        std::string text = k + "\n4 2 0\n0 0 0" + extra + "\n0 1 0" + extra + "\n";
        text += std::string(vertex) + (std::string(vertex).empty() || vertex[0] == '#' ? "" : extra) + "\n0 0 1" + extra + "\n";
        text += std::string(face) + "\n3 1 2 3\n";
        texts.push_back(text);
      }
    }
  std::size_t read = 0, refused = 0;
  check_paths_agree_on(texts, fuzz::check_off_paths_agree, read, refused);
  EXPECT_GT(read, 50u);
  EXPECT_GT(refused, 50u);
}

TEST(ObjIo, RoundTripIsExactAndStable) {
  for (std::uint64_t seed : {1, 2, 3}) {
    const ObjModel model = random_obj(10, seed);
    const Mesh mesh = obj_mesh(model.text, "model.obj");
    ASSERT_EQ(mesh.num_vertices(), model.soup.positions.size());
    const std::string first = write_to_string(mesh, MeshFormat::Obj);
    const PolygonSoup back = read_obj(first, "first.obj");
    expect_same_soup(model.soup, back, "seed " + std::to_string(seed));
    // Positions through the Mesh are identical too (==, not near).
    const Mesh again = build_mesh(back, "first.obj");
    ASSERT_EQ(again.num_vertices(), mesh.num_vertices());
    for (std::size_t v = 0; v < mesh.num_vertices(); ++v)
      ASSERT_TRUE(Eigen::Vector3d(again.positions().col(v)) == Eigen::Vector3d(mesh.positions().col(v))) << v;
    EXPECT_EQ(again.faces(), mesh.faces());
    // write(read(write(x))) == write(x), byte for byte.
    EXPECT_EQ(write_to_string(again, MeshFormat::Obj), first);
    EXPECT_NE(first.find("mtllib scene.mtl other.mtl\n"), std::string::npos);
    EXPECT_NE(first.find("g left arm\n"), std::string::npos);
  }
}

TEST(ObjIo, VertexColoursRoundTrip) {
  const std::string text =
      "v 0 0 0 1 0 0\nv 1 0 0 0 1 0\nv 0 1 0 0 0 1\nv 1 1 0 0.25 0.5 0.75\nf 1 2 4 3\n";
  const Mesh mesh = obj_mesh(text);
  ASSERT_TRUE(mesh.has_colors());
  const std::string first = write_to_string(mesh, MeshFormat::Obj);
  const PolygonSoup back = read_obj(first, "c.obj");
  const PolygonSoup orig = read_obj(text, "c.obj");
  expect_same_soup(orig, back, "colours");
  EXPECT_EQ(write_to_string(obj_mesh(first), MeshFormat::Obj), first);
}

// ---------------------------------------------------------------------------------------
// OFF round trip

struct OffModel {
  std::string text;
  PolygonSoup soup;
};

OffModel random_off(int n, std::uint64_t seed, bool colors, bool normals) {
  std::mt19937_64 rng(seed);
  OffModel m;
  PolygonSoup& s = m.soup;
  s.positions = random_positions(n, rng);
  std::uniform_int_distribution<int> byte(0, 255);
  std::uniform_real_distribution<double> unit(-1, 1);
  const auto faces = polygon_faces(n);
  std::ostringstream os;
  os << (colors ? "C" : "") << (normals ? "N" : "") << "OFF\n# comment line\n\n";
  os << s.positions.size() << " " << faces.size() << " 0\n";
  for (const auto& p : s.positions) {
    os << digits17(p.x()) << " " << digits17(p.y()) << " " << digits17(p.z());
    if (normals) {
      Eigen::Vector3d v(unit(rng), unit(rng), unit(rng));
      v.normalize();
      for (int k = 0; k < 3; ++k) v[k] = std::strtod(digits17(v[k]).c_str(), nullptr);
      s.normals.push_back(v);
      os << " " << digits17(v.x()) << " " << digits17(v.y()) << " " << digits17(v.z());
    }
    if (colors) {
      const int r = byte(rng), g = byte(rng), b = byte(rng);
      s.colors.emplace_back(static_cast<float>(r / 255.0), static_cast<float>(g / 255.0),
                            static_cast<float>(b / 255.0));
      os << " " << r << " " << g << " " << b << " 255";
    }
    os << "\n";
  }
  for (const auto& f : faces) {
    os << f.size();
    for (std::uint32_t v : f) os << " " << v;
    os << "\n";
    test::SoupFace face{f, {}, {}};
    if (normals) face.normals.assign(f.begin(), f.end());
    test::add_face(s, face.vertices, face.uvs, face.normals, face.group);
  }
  m.text = os.str();
  return m;
}

TEST(OffIo, RoundTripIsExactAndStableForEveryVariant) {
  struct Variant {
    bool colors, normals;
    const char* keyword;
  };
  for (const Variant& variant : {Variant{false, false, "OFF"}, Variant{true, false, "COFF"},
                                 Variant{false, true, "NOFF"}, Variant{true, true, "CNOFF"}}) {
    SCOPED_TRACE(variant.keyword);
    const OffModel model = random_off(9, 7, variant.colors, variant.normals);
    ASSERT_EQ(model.text.rfind(variant.keyword, 0), 0u);
    const PolygonSoup read = read_off(model.text, "model.off");
    expect_same_soup(model.soup, read, "as written vs as read");
    const Mesh mesh = build_mesh(read, "model.off");
    const std::string first = write_to_string(mesh, MeshFormat::Off);
    EXPECT_EQ(first.rfind(std::string(variant.keyword) + "\n", 0), 0u) << first.substr(0, 10);
    const PolygonSoup back = read_off(first, "first.off");
    expect_same_soup(model.soup, back, "round trip");
    const Mesh again = build_mesh(back, "first.off");
    EXPECT_EQ(again.faces(), mesh.faces());
    EXPECT_EQ(write_to_string(again, MeshFormat::Off), first);
  }
}

// A NOFF point cloud: its normals are its points' own, written back as read by OFF and as
// the same values by PLY (they were zeros: a cloud's points are in no face).
TEST(OffIo, APointCloudKeepsItsNormals) {
  const std::string cloud = "NOFF\n3 0 0\n0 0 0 0 0 1\n1 0 0 0 1 0\n0 1 0 0.6 0 0.8\n";
  const Mesh mesh = build_mesh(read_off(cloud, "cloud.off"), "cloud.off");
  EXPECT_EQ(write_to_string(mesh, MeshFormat::Off), cloud);
  const Mesh ply = build_mesh(read_ply(write_to_string(mesh, MeshFormat::Ply), "cloud.ply"), "cloud.ply");
  ASSERT_EQ(ply.file_normals().size(), 3u);
  EXPECT_EQ(ply.file_normals()[2], Eigen::Vector3d(0.6, 0, 0.8));
}

TEST(OffIo, ReadsCountsOnTheHeaderLineAndCrlf) {
  const std::string text = "OFF 4 1 0\r\n0 0 0\r\n1 0 0\r\n1 1 0\r\n0 1 0\r\n4 0 1 2 3\r\n";
  const PolygonSoup soup = read_off(text, "a.off");
  const std::vector<test::SoupFace> soup_faces = test::soup_faces(soup);
  ASSERT_EQ(soup.positions.size(), 4u);
  ASSERT_EQ(soup_faces.size(), 1u);
  EXPECT_EQ(soup_faces[0].vertices, (std::vector<std::uint32_t>{0, 1, 2, 3}));
}

// OFF is whitespace-separated: a face record may wrap over lines, its colour on the last.
TEST(OffIo, ReadsFaceRecordsWrappedOverSeveralLines) {
  const std::string text = "OFF\n5 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n2 2 1\n4 0 1\n  2 3\n3 2\n3\n4 255 0 0\n";
  for (const bool fast : {true, false}) {
    const PolygonSoup soup = fast ? read_off(text, "w.off") : read_off_general(text, "w.off");
    const std::vector<test::SoupFace> faces = test::soup_faces(soup);
    ASSERT_EQ(faces.size(), 2u);
    EXPECT_EQ(faces[0].vertices, (std::vector<std::uint32_t>{0, 1, 2, 3}));
    EXPECT_EQ(faces[0].line, 8u);
    EXPECT_EQ(faces[1].vertices, (std::vector<std::uint32_t>{2, 3, 4}));
    EXPECT_EQ(faces[1].line, 10u);
  }
  test::expect_input_error([&] { read_off("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0\n1 9\n", "w.off"); },
                           "w.off:6:", {"'9'", "out of range"});
}

// ---------------------------------------------------------------------------------------
// Agreement with independent readers

TEST(MeshIoAgreement, TinyObjLoaderReadsTheBunnyTheSame) {
  const std::string path = test::data("bunny.obj");
  tinyobj::attrib_t attrib;
  std::vector<tinyobj::shape_t> shapes;
  std::vector<tinyobj::material_t> materials;
  std::string warn, err;
  ASSERT_TRUE(tinyobj::LoadObj(&attrib, &shapes, &materials, &warn, &err, path.c_str(), nullptr,
                               /*triangulate=*/false))
      << err;
  static_assert(sizeof(tinyobj::real_t) == sizeof(double), "the test links tinyobjloader_double");

  const Mesh mesh = read_mesh(path);
  ASSERT_EQ(mesh.num_vertices(), 1839u);
  ASSERT_EQ(attrib.vertices.size(), 3 * mesh.num_vertices());
  for (std::size_t v = 0; v < mesh.num_vertices(); ++v)
    for (int k = 0; k < 3; ++k) {
      const double ours = mesh.positions()(k, static_cast<Eigen::Index>(v));
      const double theirs = attrib.vertices[3 * v + k];
      // tinyobjloader's parser is not correctly rounded; ours is (from_chars).
      ASSERT_LE(std::abs(ours - theirs), 1e-15 * std::abs(ours)) << "vertex " << v << " coordinate " << k;
    }
  // Ours is the correctly rounded value of the file's text.
  std::ifstream is(path);
  std::string line;
  std::size_t v = 0;
  while (std::getline(is, line)) {
    if (line.rfind("v ", 0) != 0) continue;
    std::istringstream ls(line.substr(2));
    for (int k = 0; k < 3; ++k) {
      std::string token;
      ls >> token;
      ASSERT_EQ(mesh.positions()(k, static_cast<Eigen::Index>(v)), std::strtod(token.c_str(), nullptr));
    }
    ++v;
  }
  EXPECT_EQ(v, mesh.num_vertices());

  std::vector<std::vector<std::uint32_t>> theirs;
  for (const tinyobj::shape_t& shape : shapes) {
    std::size_t offset = 0;
    for (unsigned char count : shape.mesh.num_face_vertices) {
      std::vector<std::uint32_t> face;
      for (unsigned c = 0; c < count; ++c)
        face.push_back(static_cast<std::uint32_t>(shape.mesh.indices[offset + c].vertex_index));
      offset += count;
      theirs.push_back(face);
    }
  }
  EXPECT_EQ(theirs.size(), 3674u);
  EXPECT_EQ(mesh.faces(), theirs);
}

TEST(MeshIoAgreement, CgalReadsOurOffTheSame) {
  std::mt19937_64 rng(11);
  PolygonSoup soup;
  soup.positions = random_positions(12, rng);
  for (const auto& f : polygon_faces(12)) {
    test::SoupFace face{f, {}, {}};
    test::add_face(soup, face.vertices, face.uvs, face.normals, face.group);
  }
  const Mesh mesh = build_mesh(soup, "soup");
  const std::string path = test::temp_folder("cgal_off") + "/ours.off";
  write_mesh(path, mesh);

  std::vector<CgalPoint> points;
  std::vector<std::vector<std::size_t>> polygons;
  ASSERT_TRUE(CGAL::IO::read_OFF(path, points, polygons));
  ASSERT_EQ(points.size(), mesh.num_vertices());
  for (std::size_t v = 0; v < points.size(); ++v)
    for (int k = 0; k < 3; ++k)
      ASSERT_EQ(points[v][k], mesh.positions()(k, static_cast<Eigen::Index>(v))) << "vertex " << v;
  const auto faces = mesh.faces();
  ASSERT_EQ(polygons.size(), faces.size());
  for (std::size_t f = 0; f < faces.size(); ++f)
    ASSERT_EQ(std::vector<std::size_t>(faces[f].begin(), faces[f].end()), polygons[f]) << "face " << f;
  for (std::size_t v = 0; v < points.size(); ++v)
    EXPECT_TRUE(Eigen::Vector3d(points[v].x(), points[v].y(), points[v].z()) == soup.positions[v]) << v;
}

Mesh random_polygon_mesh(int n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  PolygonSoup soup;
  soup.positions = random_positions(n, rng);
  for (const auto& f : polygon_faces(n)) {
    test::SoupFace face{f, {}, {}};
    test::add_face(soup, face.vertices, face.uvs, face.normals, face.group);
  }
  return build_mesh(soup, "soup");
}

// CGAL's PLY reader finds `mesh`'s positions and faces in `path` exactly, and so does ours.
void expect_cgal_reads_ply_exactly(const std::string& path, const Mesh& mesh) {
  std::ifstream is(path, std::ios::binary);
  std::vector<CgalPoint> points;
  std::vector<std::vector<std::size_t>> polygons;
  ASSERT_TRUE(CGAL::IO::read_PLY(is, points, polygons));
  ASSERT_EQ(points.size(), mesh.num_vertices());
  for (std::size_t v = 0; v < points.size(); ++v)
    for (int k = 0; k < 3; ++k)
      ASSERT_EQ(points[v][k], mesh.positions()(k, static_cast<Eigen::Index>(v))) << "vertex " << v;
  const auto faces = mesh.faces();
  ASSERT_EQ(polygons.size(), faces.size());
  for (std::size_t f = 0; f < faces.size(); ++f)
    ASSERT_EQ(std::vector<std::size_t>(faces[f].begin(), faces[f].end()), polygons[f]) << "face " << f;
  const Mesh back = read_mesh(path);
  EXPECT_EQ(back.faces(), faces);
  EXPECT_TRUE(Eigen::Matrix3Xd(back.positions()) == Eigen::Matrix3Xd(mesh.positions()));
}

TEST(MeshIoAgreement, CgalReadsOurPlyExactly) {
  const Mesh mesh = random_polygon_mesh(10, 21);
  const std::string path = test::temp_folder("cgal_ply") + "/ours.ply";
  write_mesh(path, mesh);
  expect_cgal_reads_ply_exactly(path, mesh);
}

TEST(MeshIoAgreement, CgalReadsOurStlAsTriangleFansWithMergedCorners) {
  const Mesh mesh = random_polygon_mesh(8, 31);
  const std::string path = test::temp_folder("cgal_stl") + "/ours.stl";
  write_mesh(path, mesh);
  std::ifstream is(path, std::ios::binary);
  std::vector<CgalPoint> points;
  std::vector<std::array<std::size_t, 3>> triangles;
  ASSERT_TRUE(CGAL::IO::read_STL(is, points, triangles));
  // STL repeats each corner point per triangle; equal points become one vertex.
  EXPECT_EQ(points.size(), mesh.num_vertices());
  std::vector<std::array<Eigen::Vector3d, 3>> fans;
  std::vector<std::uint32_t> ids;
  for (std::size_t f = 0; f < mesh.num_faces(); ++f) {
    mesh.face_vertices(f, ids);
    for (std::size_t i = 1; i + 1 < ids.size(); ++i)
      fans.push_back({mesh.positions().col(ids[0]), mesh.positions().col(ids[i]), mesh.positions().col(ids[i + 1])});
  }
  ASSERT_EQ(triangles.size(), fans.size());
  for (std::size_t t = 0; t < fans.size(); ++t)
    for (int c = 0; c < 3; ++c) {
      const CgalPoint& p = points[triangles[t][c]];
      ASSERT_TRUE(Eigen::Vector3d(p.x(), p.y(), p.z()) == fans[t][c]) << "triangle " << t << " corner " << c;
    }

  const Mesh back = read_mesh(path);
  EXPECT_EQ(back.num_vertices(), mesh.num_vertices());
  EXPECT_EQ(back.num_faces(), fans.size());
  EXPECT_TRUE(back.is_triangle_mesh());
}

WriteOptions binary_output() {
  WriteOptions options;
  options.encoding = WriteOptions::Encoding::Binary;
  return options;
}

TEST(MeshIoAgreement, CgalReadsOurBinaryPlyExactly) {
  const Mesh mesh = random_polygon_mesh(10, 22);
  const std::string path = test::temp_folder("cgal_binary_ply") + "/ours.ply";
  write_mesh(path, mesh, binary_output());
  ASSERT_NE(test::read_file(path).find("format binary_little_endian 1.0\n"), std::string::npos);
  expect_cgal_reads_ply_exactly(path, mesh);
  EXPECT_TRUE(read_mesh(path).source_binary());
}

TEST(MeshIoAgreement, CgalReadsOurBinaryStlAsFloat32Fans) {
  const Mesh mesh = random_polygon_mesh(8, 32);
  const std::string path = test::temp_folder("cgal_binary_stl") + "/ours.stl";
  write_mesh(path, mesh, binary_output());
  std::size_t fans = 0;
  std::vector<std::uint32_t> face;
  for (std::size_t f = 0; f < mesh.num_faces(); ++f) {
    mesh.face_vertices(f, face);
    fans += face.size() - 2;
  }
  EXPECT_EQ(std::filesystem::file_size(path), 84 + 50 * fans);  // header, count, 50 bytes a triangle
  std::ifstream is(path, std::ios::binary);
  std::vector<CgalPoint> points;
  std::vector<std::array<std::size_t, 3>> triangles;
  ASSERT_TRUE(CGAL::IO::read_STL(is, points, triangles));
  ASSERT_EQ(triangles.size(), fans);
  std::vector<std::uint32_t> ids;
  std::size_t t = 0;
  for (std::size_t f = 0; f < mesh.num_faces(); ++f) {
    mesh.face_vertices(f, ids);
    for (std::size_t i = 1; i + 1 < ids.size(); ++i, ++t)
      for (int c = 0; c < 3; ++c) {
        const Eigen::Vector3d expected = mesh.positions().col(ids[c == 0 ? 0 : i + c - 1]).cast<float>().cast<double>();
        const CgalPoint& p = points[triangles[t][c]];
        ASSERT_TRUE(Eigen::Vector3d(p.x(), p.y(), p.z()) == expected) << "triangle " << t << " corner " << c;
      }
  }
  EXPECT_TRUE(read_mesh(path).source_binary());
}

// PLY and STL outputs keep the input's encoding unless told; OBJ and OFF inputs give text.
TEST(MeshIo, PlyAndStlOutputsKeepTheInputsEncoding) {
  const std::string dir = test::temp_folder("encoding");
  const Mesh mesh = random_polygon_mesh(6, 41);
  write_mesh(dir + "/binary.stl", mesh, binary_output());
  write_mesh(dir + "/binary.ply", mesh, binary_output());
  write_mesh(dir + "/text.ply", mesh);
  const auto binary = [](const std::string& path) {
    const std::string bytes = test::read_file(path);
    return bytes.rfind("solid", 0) != 0 && bytes.find("format ascii") == std::string::npos;
  };
  for (const char* in : {"binary.stl", "binary.ply", "text.ply"})
    for (const char* ext : {".ply", ".stl"}) {
      const std::string out = dir + "/out-" + in + ext;
      write_mesh(out, read_mesh(dir + "/" + in));
      EXPECT_EQ(binary(out), std::string(in).rfind("binary", 0) == 0) << in << " -> " << ext;
    }
  WriteOptions ascii;
  ascii.encoding = WriteOptions::Encoding::Ascii;
  write_mesh(dir + "/asked.stl", read_mesh(dir + "/binary.stl"), ascii);
  EXPECT_FALSE(binary(dir + "/asked.stl"));
}

// A polygon of more than 255 corners does not fit PLY's uchar list count: an int count then.
TEST(PlyIo, PolygonsOfMoreThan255CornersRoundTrip) {
  PolygonSoup soup;
  std::vector<std::uint32_t> ring;
  for (int i = 0; i < 300; ++i) {
    const double a = 2 * M_PI * i / 300;
    soup.positions.emplace_back(std::cos(a), std::sin(a), 0.1 * std::sin(5 * a));
    ring.push_back(static_cast<std::uint32_t>(i));
  }
  soup.elements.add_polygon(ring);
  const Mesh mesh = build_mesh(soup, "ring");
  const std::string dir = test::temp_folder("ring");
  for (bool b : {false, true}) {
    const std::string path = dir + (b ? "/binary.ply" : "/text.ply");
    write_mesh(path, mesh, b ? binary_output() : WriteOptions{});
    EXPECT_NE(test::read_file(path).find("property list int int vertex_indices"), std::string::npos);
    const Mesh back = read_mesh(path);
    EXPECT_EQ(back.faces(), mesh.faces());
    EXPECT_TRUE(Eigen::Matrix3Xd(back.positions()) == Eigen::Matrix3Xd(mesh.positions()));
  }
}

// ---------------------------------------------------------------------------------------
// Bad input: InputError naming the file and the line

TEST(ObjIo, RejectsMalformedLinesWithFileAndLine) {
  const std::string head = "v 0 0 0\nv 1 0 0\n";  // lines 1-2
  const auto read = [](const std::string& text) { return [text] { obj_mesh(text, "x.obj"); }; };
  expect_input_error(read(head + "v 1 2\nf 1 2 3\n"), "x.obj:3:", {"v x y z", "2 values"});
  expect_input_error(read(head + "v 1 2 nan\nf 1 2 3\n"), "x.obj:3:", {"'nan'", "not a finite number"});
  expect_input_error(read(head + "v 1 inf 2\nf 1 2 3\n"), "x.obj:3:", {"'inf'", "not a finite number"});
  expect_input_error(read(head + "v 1 1e999 2\nf 1 2 3\n"), "x.obj:3:", {"1e999"});
  expect_input_error(read(head + "v a b c\n"), "x.obj:3:", {"'a'"});
  expect_input_error(read(head + "v 0 1 0\nf 1 2 9\n"), "x.obj:4:", {"index 9", "out of range", "3 defined"});
  expect_input_error(read(head + "v 0 1 0\nf 1 2 -4\n"), "x.obj:4:", {"out of range"});
  expect_input_error(read("f 1 2 3\n" + head + "v 0 1 0\n"), "x.obj:1:", {"out of range", "0 defined"});
  expect_input_error(read(head + "v 0 1 0\nf 0 1 2\n"), "x.obj:4:", {"'0'", "non-zero"});
  expect_input_error(read(head + "v 0 1 0\nf 1 2 x\n"), "x.obj:4:", {"'x'"});
  expect_input_error(read(head + "v 0 1 0\nvt 0 0\nf 1/1 2/5 3/1\n"), "x.obj:5:", {"texture", "out of range"});
  expect_input_error(read(head + "v 0 1 0\nf 1//1 2//1 3//1\n"), "x.obj:4:", {"normal", "out of range"});
  expect_input_error(read(head + "v 0 1 0\nf 1 2\n"), "x.obj:4:", {"at least 3"});
  // A statement keyword that is not a word (junk, UTF-16 text) is refused; words are kept.
  expect_input_error(read(head + "\x01\x02 1 2\n"), "x.obj:3:", {"unsupported OBJ statement"});
  expect_input_error(read(head + "v\xff 1 2\n"), "x.obj:3:", {"unsupported OBJ statement"});
  expect_input_error(read(head + "l 1\n"), "x.obj:3:", {"a line needs at least 2 vertices, found 1"});
  expect_input_error(read(head + "p\n"), "x.obj:3:", {"a point element needs at least 1 vertices, found 0"});
  expect_input_error(read(head + "l 1 9\n"), "x.obj:3:", {"vertex index 9 is out of range"});
  expect_input_error(read(head + "vn 0 nan 1\n"), "x.obj:3:", {"'nan'"});
  expect_input_error(read(head + "vt 0.5 inf\n"), "x.obj:3:", {"'inf'"});
  expect_input_error(read(head + "v 0 1 0 nan\n"), "x.obj:3:", {"'nan'"});
}

// build_mesh checks every reader's soup: a whole-array pass where all is in range, the walk
// naming the first bad element where not.
TEST(BuildMesh, NamesTheFirstBadElementOfASoup) {
  // Three vertices, one UV, one normal, one group; elements on lines 5, 6 and 7.
  const auto soup = [](std::uint32_t vertex, std::int32_t uv, std::int32_t normal, std::int32_t group, bool empty) {
    PolygonSoup s;
    s.positions = {Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY()};
    s.uvs = {Eigen::Vector2d::Zero()};
    s.normals = {Eigen::Vector3d::UnitZ()};
    s.groups = {ObjState{}};
    for (std::uint32_t v : {0u, 1u, 2u}) s.elements.add_corner(v, 0, 0);
    s.elements.close(ElementKind::Polygon, 0, 5);
    if (!empty)
      for (std::uint32_t v : {0u, 1u, vertex}) s.elements.add_corner(v, v == 0 ? uv : -1, v == 0 ? normal : -1);
    s.elements.close(ElementKind::Polygon, group, 6);
    for (std::uint32_t v : {2u, 1u, 9u}) s.elements.add_corner(v);  // always bad: only named when 6 is good
    s.elements.close(ElementKind::Polygon, -1, 7);
    return s;
  };
  const auto build = [](PolygonSoup s) { return [s] { build_mesh(s, "s.obj"); }; };
  expect_input_error(build(soup(2, 0, 0, 0, false)), "s.obj:7:", {"vertex index 9 is out of range", "3 vertices"});
  expect_input_error(build(soup(3, 0, 0, 0, false)), "s.obj:6:", {"vertex index 3 is out of range"});
  expect_input_error(build(soup(2, 1, 0, 0, false)), "s.obj:6:", {"texture index out of range"});
  expect_input_error(build(soup(2, 0, 1, 0, false)), "s.obj:6:", {"normal index out of range"});
  expect_input_error(build(soup(2, 0, 0, 1, false)), "s.obj:6:", {"group index out of range"});
  expect_input_error(build(soup(2, 0, 0, 0, true)), "s.obj:6:", {"at least one vertex"});
  PolygonSoup good = soup(2, -1, -1, -1, false);
  good.elements.corners.back() = 0;
  EXPECT_EQ(build_mesh(good, "s.obj").num_faces(), 3u);
}

// The spec's statements ffdtool does not interpret, `\` continuations and w components:
// read, warned about by kind, and written back in place to an OBJ.
TEST(ObjIo, KeepsWhatItDoesNotInterpretAndWritesItBackInPlace) {
  const std::string text =
      "mtllib a.mtl\nmaplib x.map\nv 0 0 0\nv 1 0 0 0.5\nv 0 1 0\nvw 2 0.25\nlod 3\nf 1 2 \\\n 3\n"
      "usemap tex\nbevel on\nf 1 3 2\ntrace_obj t.obj\n";
  const Mesh mesh = obj_mesh(text, "k.obj");
  ASSERT_NE(mesh.obj_source(), nullptr);
  EXPECT_EQ(mesh.num_faces(), 2u);
  EXPECT_EQ(mesh.faces()[0], (std::vector<std::uint32_t>{0, 1, 2}));
  const std::vector<std::string> notes = uninterpreted_data(mesh);
  ASSERT_EQ(notes.size(), 6u);
  EXPECT_EQ(notes[0], "1 OBJ 'maplib' statement is not interpreted; an OBJ output writes it back in place");
  std::ostringstream os;
  write_mesh(os, MeshFormat::Obj, mesh);
  EXPECT_EQ(os.str(), "mtllib a.mtl\nmaplib x.map\nv 0 0 0\nv 1 0 0 0.5\nv 0 1 0\nvw 2 0.25\nlod 3\nf 1 2 3\n"
                      "usemap tex\nbevel on\nf 1 3 2\ntrace_obj t.obj\n");
  EXPECT_EQ(unwritten_data(mesh, MeshFormat::Obj), "");
  EXPECT_EQ(unwritten_data(mesh, MeshFormat::Ply),
            "the OBJ file's 'maplib', 'vw', 'lod', 'usemap', 'bevel', 'trace_obj' statements and w components "
            "(only an OBJ holds them) are not written");
  // The fast and the general path keep the same.
  EXPECT_EQ(read_obj_general(text, "k.obj").obj->statements.size(), read_obj(text, "k.obj").obj->statements.size());
}

TEST(ObjIo, TheManifoldCheckNamesTheFileLine) {
  const std::string verts = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 -1 0\nv 0.5 0.5 1\n";  // lines 1-5
  const auto checked = [&](const std::string& faces) {
    return [&verts, faces] { check_two_manifold(obj_mesh(verts + faces, "x.obj")); };
  };
  // Three faces on the edge (1, 2).
  expect_input_error(checked("f 1 2 3\nf 2 1 4\nf 1 2 5\n"), "x.obj:8:", {"non-manifold edge 0–1"});
  // Two faces using the edge (1, 2) in the same direction.
  expect_input_error(checked("f 1 2 3\nf 1 2 4\n"), "x.obj:7:", {"flipped against its neighbour face 0 (line 6)"});
  // A face repeating a vertex.
  expect_input_error(checked("f 1 2 3\nf 2 4 1 4\n"), "x.obj:7:", {"degenerate", "twice"});
  expect_input_error(checked("f 1 2 1\n"), "x.obj:6:", {"twice"});
  // Lines and points are not faces: the check passes over them.
  EXPECT_NO_THROW(check_two_manifold(obj_mesh(verts + "f 1 2 3\nl 1 2 3 4\np 5\nl 1 2\n", "x.obj")));
}

TEST(ObjIo, ReadMeshNamesThePathAndLine) {
  const std::string dir = test::temp_folder("obj_errors");
  test::write_file(dir + "/bad.obj", "# header\nv 0 0 0\nv 1 2\n");
  expect_input_error([&] { read_mesh(dir + "/bad.obj"); }, dir + "/bad.obj:3:", {"2 values"});
  expect_input_error([&] { read_mesh(dir + "/missing.obj"); }, dir + "/missing.obj:", {"no such file"});
  expect_input_error([&] { read_mesh(dir + "/mesh.xyz"); }, dir + "/mesh.xyz:", {"unknown mesh format"});
}

// Never trust a header; a file with no vertex is not a mesh (whatever its format).
TEST(MeshIo, HugeCountsAndFilesWithoutVerticesAreInputErrors) {
  expect_input_error([] { read_off("OFF\n1000000000000 1 0\n0 0 0\n", "x.off"); }, "x.off:2:",
                     {"1000000000000 vertices", "more than the file's 28 bytes can hold"});
  const std::string dir = test::temp_folder("mesh_io_empty");
  for (const char* name : {"empty.obj", "comment.obj", "zero.off"}) {
    const std::string path = dir + "/" + name;
    test::write_file(path, std::string(name) == "comment.obj" ? "# nothing here\n" : std::string(name) == "zero.off" ? "OFF\n0 0 0\n" : "");
    expect_input_error([path] { read_mesh(path); }, path + ": ", {"no vertex"});
  }
}

TEST(OffIo, RejectsMalformedFilesWithFileAndLine) {
  const auto read = [](const std::string& text) { return [text] { build_mesh(read_off(text, "x.off"), "x.off"); }; };
  const std::string tri = "0 0 0\n1 0 0\n0 1 0\n";  // lines 3-5 after "OFF\nn f e\n"
  // Sanity: the well-formed file reads.
  EXPECT_NO_THROW(read("OFF\n3 1 0\n" + tri + "3 0 1 2\n")());
  // More vertices promised than given: the face line is read as a vertex.
  expect_input_error(read("OFF\n4 1 0\n" + tri + "3 0 1 2\n"), "x.off:6:", {"vertex 3"});
  // More faces promised than given: names the header line with the count.
  expect_input_error(read("OFF\n3 2 0\n" + tri + "3 0 1 2\n"), "x.off:2:", {"2 faces"});
  expect_input_error(read("OFF\n5 1 0\n" + tri), "x.off:2:", {"5 vertices"});
  EXPECT_NO_THROW(read("OFF\n3 1\n" + tri + "3 0 1 2\n")());  // the edge count may be left out
  expect_input_error(read("OFF\n3 x 0\n" + tri + "3 0 1 2\n"), "x.off:2:", {"count"});
  // A vertex line with a missing coordinate; a non-finite one.
  expect_input_error(read("OFF\n3 1 0\n0 0 0\n1 0\n0 1 0\n3 0 1 2\n"), "x.off:4:", {"vertex 1", "found 2"});
  expect_input_error(read("OFF\n3 1 0\n0 0 0\n1 nan 0\n0 1 0\n3 0 1 2\n"), "x.off:4:", {"'nan'"});
  expect_input_error(read("OFF\n3 1 0\n0 0 0\n1 0 inf\n0 1 0\n3 0 1 2\n"), "x.off:4:", {"'inf'"});
  // Faces: index out of range, too few indices, wrong vertex count.
  expect_input_error(read("OFF\n3 1 0\n" + tri + "3 0 1 7\n"), "x.off:6:", {"'7'", "out of range"});
  expect_input_error(read("OFF\n3 1 0\n" + tri + "3 0 1 -1\n"), "x.off:6:", {"out of range"});
  expect_input_error(read("OFF\n3 1 0\n" + tri + "3 0 1\n"), "x.off:6:", {"2 of its 3"});
  expect_input_error(read("OFF\n3 1 0\n" + tri + "2 0 1\n"), "x.off:6:", {"3 or more"});
  // Trailing garbage after the last face.
  expect_input_error(read("OFF\n3 1 0\n" + tri + "3 0 1 2\n\njunk\n"), "x.off:8:", {"after the last face"});
  // Binary OFF and unknown variants.
  expect_input_error(read("OFF BINARY\n3 1 0\n"), "x.off:1:", {"binary"});
  expect_input_error(read("4OFF\n3 1 0\n" + tri + "3 0 1 2\n"), "x.off:1:", {"'4OFF'"});
}

// A space warp takes any polygon soup; the 2-manifold check (remesh, bcm) names the face.
TEST(OffIo, ReadsNonManifoldAndMisorientedFacesAndTheCheckNamesThem) {
  const std::string verts = "OFF\n5 3 0\n0 0 0\n1 0 0\n0 1 0\n0 -1 0\n0.5 0.5 1\n";  // faces from line 8
  const auto checked = [](const std::string& text) {
    return [text] { check_two_manifold(build_mesh(read_off(text, "x.off"), "x.off")); };
  };
  EXPECT_EQ(build_mesh(read_off(verts + "3 0 1 2\n3 1 0 3\n3 0 1 4\n", "x.off"), "x.off").num_faces(), 3u);
  expect_input_error(checked(verts + "3 0 1 2\n3 1 0 3\n3 0 1 4\n"), "x.off:10:",
                     {"non-manifold edge 0–1", "face 2 is its third face, after face 0 (line 8) and face 1 (line 9)"});
  expect_input_error(checked("OFF\n4 2 0\n0 0 0\n1 0 0\n0 1 0\n0 -1 0\n3 0 1 2\n3 0 1 3\n"), "x.off:8:",
                     {"face 1 is flipped against its neighbour face 0 (line 7): both run 0→1"});
  expect_input_error(checked("OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n3 1 2 0\n"), "x.off:7:",
                     {"face 1 duplicates face 0 (line 6)"});
  expect_input_error(checked("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 1\n"), "x.off:6:",
                     {"degenerate face 0: it uses vertex 1 twice"});
  // Two fans meeting at vertex 0 (a bow tie): every edge is fine, the vertex is not.
  expect_input_error(checked("OFF\n5 2 0\n0 0 0\n1 0 0\n1 1 0\n-1 0 0\n-1 -1 0\n3 0 1 2\n3 0 3 4\n"), "x.off:9:",
                     {"non-manifold vertex 0"});
  EXPECT_NO_THROW(check_two_manifold(build_mesh(read_off(verts + "3 0 1 2\n3 1 0 3\n3 1 4 2\n", "x.off"), "x.off")));
}

// ---------------------------------------------------------------------------------------
// build_mesh keeps the file's order

TEST(BuildMesh, KeepsVertexOrderAndEachFacesFirstVertex) {
  std::mt19937_64 rng(5);
  const int n = 9;
  const auto grid = polygon_faces(n);
  const int nv = polygon_vertex_count(n);
  // A random relabelling of the vertices, an isolated vertex, and faces starting anywhere.
  std::vector<std::uint32_t> label(nv);
  std::iota(label.begin(), label.end(), 0u);
  std::shuffle(label.begin(), label.end(), rng);
  PolygonSoup soup;
  const std::vector<Eigen::Vector3d> base = random_positions(n, rng);
  soup.positions.resize(nv + 1);
  for (int v = 0; v < nv; ++v) soup.positions[label[v]] = base[v];
  soup.positions[nv] = Eigen::Vector3d(100, 200, 300);  // isolated
  std::vector<std::vector<std::uint32_t>> expect;
  for (const auto& f : grid) {
    std::vector<std::uint32_t> face;
    for (std::uint32_t v : f) face.push_back(label[v]);
    std::rotate(face.begin(), face.begin() + rng() % face.size(), face.end());
    expect.push_back(face);
  }
  std::shuffle(expect.begin(), expect.end(), rng);  // any face order
  for (const auto& face : expect) test::add_face(soup, face);

  const Mesh mesh = build_mesh(soup, "soup");
  ASSERT_EQ(mesh.num_vertices(), soup.positions.size());
  for (std::size_t v = 0; v < soup.positions.size(); ++v) {
    EXPECT_TRUE(Eigen::Vector3d(mesh.positions().col(v)) == soup.positions[v]) << v;
    EXPECT_TRUE(Eigen::Vector3d(mesh.rest_positions().col(v)) == soup.positions[v]) << v;
  }
  EXPECT_EQ(mesh.faces(), expect);
  // The OBJ writer writes them the same way.
  const PolygonSoup back = read_obj(write_to_string(mesh, MeshFormat::Obj), "back.obj");
  const std::vector<test::SoupFace> back_faces = test::soup_faces(back);
  ASSERT_EQ(back_faces.size(), expect.size());
  for (std::size_t f = 0; f < expect.size(); ++f) EXPECT_EQ(back_faces[f].vertices, expect[f]) << f;
  EXPECT_EQ(back.positions.size(), soup.positions.size());
}

// ---------------------------------------------------------------------------------------
// Attributes through a deformation

std::vector<std::string> lines_starting(const std::string& text, const std::string& prefix) {
  std::vector<std::string> out;
  std::istringstream is(text);
  std::string line;
  while (std::getline(is, line))
    if (line.rfind(prefix, 0) == 0) out.push_back(line);
  return out;
}

// A wavy quad grid in the writer's canonical form, each face corner with its own UV
// (seams everywhere) and, when asked, file normals: faces alternately flat-shaded (one vn
// shared by the face's corners) and smooth (one vn per vertex, shared across faces).
std::string attribute_grid(int n, bool uvs, bool normals) {
  const auto height = [](double x, double y) { return 0.2 * std::sin(3 * x) * std::cos(2 * y); };
  const PolygonSoup grid = test::grid_soup(n, height, true);
  const std::vector<test::SoupFace> grid_faces = test::soup_faces(grid);
  std::string text = "mtllib grid.mtl\n";
  for (const auto& p : grid.positions) {
    text += "v ";
    append_number(text, p.x());
    text += " ";
    append_number(text, p.y());
    text += " ";
    append_number(text, p.z());
    text += "\n";
  }
  std::vector<std::string> corner_uv;
  if (uvs) {
    int t = 0;
    for (std::size_t f = 0; f < grid_faces.size(); ++f)
      for (std::size_t c = 0; c < grid_faces[f].vertices.size(); ++c) {
        const Eigen::Vector3d& p = grid.positions[grid_faces[f].vertices[c]];
        text += "vt ";
        append_number(text, p.x() * 0.9 + 0.01 * static_cast<double>(f % 3));
        text += " ";
        append_number(text, p.y() * 0.9 + 0.001 * static_cast<double>(c));
        text += "\n";
        corner_uv.push_back(std::to_string(++t));
      }
  }
  std::vector<std::string> vertex_vn(grid.positions.size()), face_vn(grid_faces.size());
  if (normals) {
    int k = 0;
    const auto add = [&](Eigen::Vector3d v) {
      v.normalize();
      text += "vn ";
      append_number(text, v.x());
      text += " ";
      append_number(text, v.y());
      text += " ";
      append_number(text, v.z());
      text += "\n";
      return std::to_string(++k);
    };
    for (std::size_t v = 0; v < grid.positions.size(); ++v) {
      const Eigen::Vector3d& p = grid.positions[v];
      vertex_vn[v] = add(Eigen::Vector3d(-0.6 * std::cos(3 * p.x()) * std::cos(2 * p.y()),
                                         0.4 * std::sin(3 * p.x()) * std::sin(2 * p.y()), 1.0));
    }
    for (std::size_t f = 0; f < grid_faces.size(); ++f)
      face_vn[f] = add(Eigen::Vector3d(0.1 * static_cast<double>(f % 5), -0.2, 1.0));
  }
  text += "g sheet\nusemtl paper\n";
  int corner = 0;
  for (std::size_t f = 0; f < grid_faces.size(); ++f) {
    text += "f";
    for (std::uint32_t v : grid_faces[f].vertices) {
      text += " " + std::to_string(v + 1);
      if (uvs || normals) text += "/";
      if (uvs) text += corner_uv[corner];
      if (normals) text += "/" + (f % 2 ? face_vn[f] : vertex_vn[v]);
      ++corner;
    }
    text += "\n";
  }
  return text;
}

std::string run_on(const std::string& name, const std::string& mesh_text, const std::string& script) {
  const std::string dir = test::temp_folder(name);
  test::write_file(dir + "/in.obj", mesh_text);
  test::write_file(dir + "/script.json", script);
  RunOptions options;
  options.mesh = dir + "/in.obj";
  options.script = dir + "/script.json";
  options.output = dir + "/out.obj";
  options.quiet = true;
  run_script(options);
  return test::read_file(dir + "/out.obj");
}

TEST(MeshAttributes, UvsSurviveADeformation) {
  const std::string input = attribute_grid(8, true, false);
  const std::string output = run_on("uv_run", input,
                                    R"({"version": 1, "steps": [
        {"op": "lattice", "name": "l", "cells": [4, 4, 4]},
        {"op": "move", "lattice": "l", "points": [{"index": [2, 2, 2], "by": [0.05, 0.1, 0.2]}]}]})");
  // The UV table and every face's corner strings are unchanged...
  EXPECT_EQ(lines_starting(output, "vt "), lines_starting(input, "vt "));
  EXPECT_EQ(lines_starting(output, "f "), lines_starting(input, "f "));
  EXPECT_EQ(lines_starting(output, "g "), lines_starting(input, "g "));
  EXPECT_EQ(lines_starting(output, "mtllib "), lines_starting(input, "mtllib "));
  EXPECT_FALSE(lines_starting(input, "vt ").empty());
  // ...while the positions moved.
  const PolygonSoup in = read_obj(input, "in.obj"), out = read_obj(output, "out.obj");
  const std::vector<test::SoupFace> in_faces = test::soup_faces(in);
  const std::vector<test::SoupFace> out_faces = test::soup_faces(out);
  ASSERT_EQ(in.positions.size(), out.positions.size());
  std::size_t moved = 0;
  double largest = 0;
  for (std::size_t v = 0; v < in.positions.size(); ++v) {
    moved += in.positions[v] != out.positions[v];
    largest = std::max(largest, (in.positions[v] - out.positions[v]).norm());
  }
  EXPECT_GT(moved, in.positions.size() / 4);
  EXPECT_GT(largest, 0.05);
  EXPECT_EQ(in.uvs, out.uvs);
  for (std::size_t f = 0; f < in_faces.size(); ++f) EXPECT_EQ(in_faces[f].uvs, out_faces[f].uvs);
}

// The cofactor of J times n, from J's columns: cof(J) = [b×c, c×a, a×b].
Eigen::Vector3d cofactor_normal(const Eigen::Matrix3d& J, const Eigen::Vector3d& n) {
  const Eigen::Vector3d a = J.col(0), b = J.col(1), c = J.col(2);
  return n[0] * b.cross(c) + n[1] * c.cross(a) + n[2] * a.cross(b);
}

TEST(MeshAttributes, FileNormalsAreTransformedByTheCofactor) {
  const std::string input = attribute_grid(10, true, true);
  const PolygonSoup in = read_obj(input, "in.obj");
  const std::vector<test::SoupFace> in_faces = test::soup_faces(in);
  Mesh mesh = build_mesh(in, "in.obj");
  WarpStack stack;
  auto owned = std::make_unique<BSplineLattice>(fit_aabb(mesh.positions(), {}, 0.1), Index3{5, 5, 5}, 3);
  BSplineLattice* lattice = owned.get();
  stack.push(mesh, "l", std::move(owned));
  lattice->move_point({2, 2, 2}, lattice->point({2, 2, 2}) + Eigen::Vector3d(0.1, -0.05, 0.2));
  lattice->move_point({3, 2, 3}, lattice->point({3, 2, 3}) + Eigen::Vector3d(-0.1, 0.1, -0.15));
  lattice->move_point({3, 3, 2}, lattice->point({3, 3, 2}) + Eigen::Vector3d(0.0, 0.15, 0.1));
  stack.update(mesh, "l");

  WriteOptions options;
  options.transform_normal = [&](std::uint32_t v, const Eigen::Vector3d& n) { return stack.transform_normal(mesh, v, n); };
  const std::string output = write_to_string(mesh, MeshFormat::Obj, options);
  const PolygonSoup out = read_obj(output, "out.obj");
  const std::vector<test::SoupFace> out_faces = test::soup_faces(out);
  ASSERT_EQ(out_faces.size(), in_faces.size());
  EXPECT_EQ(lines_starting(output, "vt "), lines_starting(input, "vt "));

  std::size_t corners = 0, changed = 0;
  for (std::size_t f = 0; f < in_faces.size(); ++f) {
    ASSERT_EQ(in_faces[f].vertices, out_faces[f].vertices);
    ASSERT_EQ(out_faces[f].normals.size(), in_faces[f].vertices.size());
    for (std::size_t c = 0; c < in_faces[f].vertices.size(); ++c) {
      const std::uint32_t v = in_faces[f].vertices[c];
      const Eigen::Vector3d n_in = in.normals[in_faces[f].normals[c]];
      const Eigen::Vector3d n_out = out.normals[out_faces[f].normals[c]];
      // Exactly the warp stack's transformed normal (the file holds it round-trip exact)...
      ASSERT_TRUE(n_out == stack.transform_normal(mesh, v, n_in)) << "face " << f << " corner " << c;
      // ...which is the normalized cofactor-transformed normal, of unit length...
      Eigen::Matrix3d J;
      stack.evaluate(Eigen::Vector3d(mesh.rest_positions().col(v)), &J);
      const Eigen::Vector3d expect = cofactor_normal(J, n_in).normalized();
      EXPECT_LT((n_out - expect).norm(), 1e-13) << "face " << f << " corner " << c;
      EXPECT_NEAR(n_out.norm(), 1.0, 1e-15 * 4);
      // ...and perpendicular to the deformed tangents.
      const Eigen::Vector3d t1 = n_in.unitOrthogonal(), t2 = n_in.cross(t1);
      EXPECT_LT(std::abs(n_out.dot(J * t1)), 1e-12 * (J * t1).norm());
      EXPECT_LT(std::abs(n_out.dot(J * t2)), 1e-12 * (J * t2).norm());
      changed += n_out != n_in;
      ++corners;
    }
  }
  EXPECT_GT(changed, corners / 10) << "the deformation should change many normals";
  EXPECT_LT(changed, corners) << "vertices outside the moved cells keep their normals";
}

TEST(MeshAttributes, IdentityRunWritesTheNormalTableUnchanged) {
  const std::string input = attribute_grid(6, true, true);
  for (const char* script : {R"({"version": 1, "steps": [{"op": "lattice", "name": "l", "cells": [4, 4, 4]}]})",
                             R"({"version": 1, "steps": [{"op": "lattice", "name": "l", "cells": [4, 4, 4]},
                                 {"op": "move", "lattice": "l", "points": [{"index": [2, 2, 2], "by": [0, 0, 0]}]}]})"}) {
    const std::string output = run_on("identity_run", input, script);
    EXPECT_FALSE(lines_starting(input, "vn ").empty());
    EXPECT_EQ(lines_starting(output, "vn "), lines_starting(input, "vn "));
    EXPECT_EQ(lines_starting(output, "f "), lines_starting(input, "f "));
    EXPECT_EQ(lines_starting(output, "vt "), lines_starting(input, "vt "));
    EXPECT_EQ(output, input) << "an identity run rewrites the file it read, byte for byte";
  }
}

}  // namespace
}  // namespace ffd
