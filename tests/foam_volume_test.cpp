// The OpenFOAM polyMesh reader (lib/mesh/foam_io.h) on the cavity meshes of
// test_data/volume (tests/python/make_polymesh.py, ASCII and binary) and the fuzz seeds:
// the cells' geometry checked independently (volumes by the divergence theorem, closed
// outward faces), the patches, the points file written back, and each refusal's place.
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "common/errors.h"
#include "mesh/foam_io.h"

namespace ffd {
namespace foam_test {

namespace fs = std::filesystem;

const fs::path kVolume = fs::path(FFD_TEST_DATA) / "volume";
const fs::path kSeeds = fs::path(FFD_TEST_DATA) / ".." / "tests" / "fuzz" / "corpus" / "foam";
constexpr const char* kNames[5] = {"points", "faces", "owner", "neighbour", "boundary"};

std::string slurp(const fs::path& path) {
  std::ifstream is(path, std::ios::binary);
  std::stringstream ss;
  ss << is.rdbuf();
  return ss.str();
}

SharedBytes shared(std::string bytes) { return std::make_shared<const FileBytes>(std::move(bytes)); }
std::string text_of(const SharedBytes& bytes) { return std::string(bytes->view()); }

FoamFiles files_of(const fs::path& folder) {
  return {shared(slurp(folder / "points")), shared(slurp(folder / "faces")), shared(slurp(folder / "owner")),
          shared(slurp(folder / "neighbour")), shared(slurp(folder / "boundary"))};
}

std::string written(const VolumeRead& r, const Eigen::Matrix3Xd& positions) {
  std::ostringstream os;
  r.source.file->write(os, positions);
  return os.str();
}

// Cell c's faces from VTK's stream form, as point lists.
std::vector<std::vector<Eigen::Vector3d>> cell_faces(const VolumeRead& r, std::size_t c) {
  const VolumeCells& cells = r.source.cells;
  const std::uint32_t* s = cells.face.data() + cells.face_offset[c];
  std::vector<std::vector<Eigen::Vector3d>> faces(*s++);
  for (auto& face : faces) {
    const std::uint32_t n = *s++;
    for (std::uint32_t k = 0; k < n; ++k) face.push_back(r.points.col(*s++));
  }
  return faces;
}

// A face's area vector and its share of the cell's volume (the divergence theorem on the
// triangles fanned from the face's mean point: sum of a . (b x c) / 6).
void face_integrals(const std::vector<Eigen::Vector3d>& face, Eigen::Vector3d& area, double& volume) {
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const auto& p : face) mean += p;
  mean /= static_cast<double>(face.size());
  area.setZero();
  volume = 0;
  for (std::size_t k = 0; k < face.size(); ++k) {
    const Eigen::Vector3d& a = face[k];
    const Eigen::Vector3d& b = face[(k + 1) % face.size()];
    area += (a - mean).cross(b - mean) / 2;
    volume += mean.dot(a.cross(b)) / 6;
  }
}

// Every polyhedron closes (its outward area vectors sum to 0) and has a positive volume;
// their volumes sum to the box's; the patches' faces are the boundary cells after them.
void expect_closed_box(const VolumeRead& r, std::size_t cells, std::size_t boundary) {
  const VolumeCells& vc = r.source.cells;
  ASSERT_EQ(vc.size(), cells + boundary);
  const Eigen::Vector3d size = r.points.rowwise().maxCoeff() - r.points.rowwise().minCoeff();
  const double box = size.prod(), scale = size.maxCoeff();
  double total = 0;
  for (std::size_t c = 0; c < cells; ++c) {
    ASSERT_EQ(vc.type[c], cell_type::kPolyhedron);
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    double volume = 0;
    for (const auto& face : cell_faces(r, c)) {
      Eigen::Vector3d a;
      double v;
      face_integrals(face, a, v);
      sum += a, volume += v;
    }
    EXPECT_LT(sum.norm(), 1e-12 * scale * scale) << "cell " << c;
    EXPECT_GT(volume, 0) << "cell " << c;
    total += volume;
  }
  EXPECT_NEAR(total, box, 1e-12 * box);
  std::size_t marked = 0;
  for (const VolumeMarker& m : r.source.markers) {
    EXPECT_EQ(m.dimension, 2);
    for (std::uint64_t c : m.cells) EXPECT_EQ(vc.type[c], cell_type::kQuad) << m.name;
    marked += m.cells.size();
  }
  EXPECT_EQ(marked, boundary);
}

// The message of the refusal of `files`, or "accepted".
std::string refusal(const FoamFiles& files) {
  try {
    read_foam_files(files, "cav");
  } catch (const InputError& e) {
    return e.what();
  }
  return "accepted";
}

// The file `which` of `files` with its text `from` replaced by `to` (first occurrence
// after `after`).
FoamFiles edited(FoamFiles files, int which, const std::string& from, const std::string& to,
                 std::size_t after = 0) {
  SharedBytes* slots[5] = {&files.points, &files.faces, &files.owner, &files.neighbour, &files.boundary};
  std::string text = text_of(*slots[which]);
  const std::size_t at = text.find(from, after);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) text.replace(at, from.size(), to);
  *slots[which] = shared(std::move(text));
  return files;
}

std::size_t line_at(const std::string& text, std::size_t offset) {
  return 1 + static_cast<std::size_t>(std::count(text.begin(), text.begin() + offset, '\n'));
}

// The byte just after a list's '(' that follows "\n<count>\n" in a binary file.
std::size_t data_start(const std::string& text, const std::string& count) {
  return text.find("\n" + count + "\n(") + count.size() + 3;
}

struct TempFolder {
  fs::path path = fs::temp_directory_path() / ("ffd_foam_test_" + std::to_string(std::random_device{}()));
  TempFolder() { fs::create_directories(path); }
  ~TempFolder() { fs::remove_all(path); }
};

}  // namespace foam_test

using namespace foam_test;

TEST(FoamRead, AsciiCavityCellsPatchesAndCompanions) {
  const VolumeRead r = read_foam((kVolume / "cavity_ascii").string());
  EXPECT_EQ(r.source.format, VolumeFormat::Foam);
  EXPECT_EQ(r.source.encoding, "ascii");
  EXPECT_EQ(r.source.version, "2.0");
  EXPECT_EQ(r.points.cols(), 5 * 4 * 3);
  expect_closed_box(r, 24, 52);
  ASSERT_EQ(r.source.markers.size(), 3u);
  EXPECT_EQ(r.source.markers[0].name, "movingWall");
  EXPECT_EQ(r.source.markers[0].cells.size(), 8u);
  EXPECT_EQ(r.source.markers[1].name, "fixedWalls");
  EXPECT_EQ(r.source.markers[1].cells.size(), 20u);
  EXPECT_EQ(r.source.markers[2].name, "frontAndBack");
  EXPECT_EQ(r.source.markers[2].cells.size(), 24u);
  EXPECT_EQ(r.source.markers[0].cells.front(), 24u);  // right after the polyhedra
  EXPECT_EQ(r.source.companion_files, (std::vector<std::string>{"cellZones", "sets/lidCells"}));
  // A hex cell: 8 distinct nodes, 6 quads.
  EXPECT_EQ(r.source.cells.degree(0), 8u);
  EXPECT_EQ(r.source.cells.face[r.source.cells.face_offset[0]], 6u);
  // The movingWall faces lie on y = 0.1 and point up (+y) out of the box.
  for (std::uint64_t c : r.source.markers[0].cells) {
    const std::uint32_t* v = r.source.cells.nodes(c);
    const Eigen::Vector3d p0 = r.points.col(v[0]), p1 = r.points.col(v[1]), p2 = r.points.col(v[2]);
    EXPECT_DOUBLE_EQ(p0.y(), 0.1);
    EXPECT_GT((p1 - p0).cross(p2 - p0).y(), 0);
  }
}

TEST(FoamRead, BinaryCavityHasTheAsciiCells) {
  const VolumeRead a = read_foam((kVolume / "cavity_ascii").string());
  const VolumeRead b = read_foam((kVolume / "cavity_binary").string());
  EXPECT_EQ(b.source.encoding, "binary");
  expect_closed_box(b, 24, 52);
  EXPECT_EQ(a.source.cells.type, b.source.cells.type);
  EXPECT_EQ(a.source.cells.node, b.source.cells.node);
  EXPECT_EQ(a.source.cells.face, b.source.cells.face);
  ASSERT_EQ(a.source.markers.size(), b.source.markers.size());
  for (std::size_t i = 0; i < a.source.markers.size(); ++i)
    EXPECT_EQ(a.source.markers[i].cells, b.source.markers[i].cells);
  EXPECT_LT((a.points - b.points).cwiseAbs().maxCoeff(), 1e-6);  // ASCII has 6 digits
  EXPECT_EQ(b.source.companion_files, a.source.companion_files);
}

TEST(FoamRead, FuzzSeedsAreClosedBoxes) {
  struct Seed {
    const char* name;
    std::size_t cells, boundary;
  };
  for (const Seed& s : {Seed{"ascii_list_2x2x1", 4, 16}, Seed{"ascii_compact_2x1x1", 2, 10},
                        Seed{"binary_label64_float_2x2x2", 8, 24}, Seed{"binary_facelist_1x2x1", 2, 10}}) {
    SCOPED_TRACE(s.name);
    const VolumeRead r = read_foam_files(split_foam_bundle(slurp(kSeeds / s.name)), s.name);
    expect_closed_box(r, s.cells, s.boundary);
  }
}

TEST(FoamRead, Float32PointsAreReadAndWrittenAsFloats) {
  const FoamFiles files = split_foam_bundle(slurp(kSeeds / "binary_label64_float_2x2x2"));
  const VolumeRead r = read_foam_files(files, "f32");
  EXPECT_EQ(r.points(0, 1), static_cast<double>(0.05f));  // x of point 1: 0.1 / 2 as a float
  Eigen::Matrix3Xd moved = r.points;
  moved(1, 4) = 0.0123456789;
  const VolumeRead again = read_foam_files({shared(written(r, moved)), files.faces, files.owner, files.neighbour,
                                            files.boundary}, "f32");
  EXPECT_EQ(again.points(1, 4), static_cast<double>(0.0123456789f));
  EXPECT_EQ(written(r, r.points), text_of(files.points));
}

TEST(FoamWrite, PositionsAsReadGiveTheSameBytes) {
  for (const char* name : {"cavity_ascii", "cavity_binary"}) {
    const VolumeRead r = read_foam((kVolume / name).string());
    EXPECT_EQ(written(r, r.points), slurp(kVolume / name / "points")) << name;
  }
}

TEST(FoamWrite, MovedNodesReadBackExactlyAndTheRestStays) {
  for (const char* name : {"cavity_ascii", "cavity_binary"}) {
    SCOPED_TRACE(name);
    const fs::path source = kVolume / name;
    const VolumeRead r = read_foam(source.string());
    Eigen::Matrix3Xd moved = r.points;
    for (Eigen::Index i = 0; i < moved.cols(); i += 2)  // every other node, by an irrational amount
      moved.col(i) += Eigen::Vector3d(std::sqrt(2.0), std::sqrt(3.0), std::sqrt(5.0)) * 1e-3 * static_cast<double>(i);
    TempFolder out;
    fs::copy(source, out.path, fs::copy_options::recursive);
    const std::string text = written(r, moved);
    std::ofstream(out.path / "points", std::ios::binary) << text;
    const VolumeRead again = read_foam(out.path.string());
    EXPECT_EQ(again.points, moved);
    EXPECT_EQ(again.source.cells.face, r.source.cells.face);
    EXPECT_EQ(again.source.companion_files, r.source.companion_files);
    // The header, the footer and the unmoved nodes' bytes are the original's.
    const std::string old = slurp(source / "points");
    const std::size_t header = old.find("\n60\n(");
    EXPECT_EQ(text.substr(0, header), old.substr(0, header));
    EXPECT_EQ(text.substr(text.size() - 80), old.substr(old.size() - 80));
    if (std::string(name) == "cavity_ascii") {
      const std::size_t p1 = old.find("\n(", old.find("\n(", header + 5) + 1);  // point 1's line: unmoved
      EXPECT_NE(text.find(old.substr(p1, old.find('\n', p1 + 1) - p1)), std::string::npos);
    } else {
      EXPECT_EQ(text.size(), old.size());
      const std::size_t data = data_start(old, "60");
      EXPECT_EQ(text.substr(data + 24, 24), old.substr(data + 24, 24));  // point 1
    }
  }
}

TEST(FoamRefuse, MissingAndCompressedFilesByName) {
  TempFolder out;
  fs::copy(kVolume / "cavity_ascii", out.path, fs::copy_options::recursive);
  fs::remove(out.path / "neighbour");
  try {
    read_foam(out.path.string());
    FAIL() << "accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), (out.path / "neighbour").string() +
              ": no such file (a polyMesh folder has points, faces, owner, neighbour and boundary)");
  }
  fs::copy(kVolume / "cavity_ascii" / "neighbour", out.path / "neighbour");
  fs::rename(out.path / "points", out.path / "points.gz");
  try {
    read_foam(out.path.string());
    FAIL() << "accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), (out.path / "points.gz").string() +
              ": compressed polyMesh files (points.gz) are not supported; gunzip them, or set writeCompression off "
              "and run foamFormatConvert");
  }
  EXPECT_THROW(read_foam((out.path / "nowhere").string()), InputError);
}

TEST(FoamRefuse, AsciiErrorsNameTheFileAndLine) {
  const FoamFiles files = files_of(kVolume / "cavity_ascii");
  const std::string& faces = text_of(files.faces);
  const std::size_t face0 = faces.find("4(1 6 26 21)");  // the +x face of cell 0
  const std::string l = std::to_string(line_at(faces, face0));
  EXPECT_EQ(refusal(edited(files, 1, "4(1 6 26 21)", "4(1 99 26 21)")),
            "cav/faces:" + l + ": label 99 out of range (the mesh has 60 points)");
  EXPECT_EQ(refusal(edited(files, 1, "4(1 6 26 21)", "2(1 6)")),
            "cav/faces:" + l + ": face 0 has 2 points (a face needs 3 or more)");
  EXPECT_EQ(refusal(edited(files, 1, "4(1 6 26 21)", "4(1 x 26 21)")),
            "cav/faces:" + l + ": expected a label (0 to 4294967295) in the face's point labels, found 'x'");
  const std::string& owner = text_of(files.owner);
  const std::string count_line = std::to_string(line_at(owner, owner.find("\n98\n") + 1));
  EXPECT_EQ(refusal(edited(edited(files, 2, "\n98\n", "\n97\n"), 2, "\n23\n)", "\n)")),
            "cav/owner:" + count_line + ": owner has 97 labels, but faces has 98 faces (one label per face)");
  const std::size_t close = owner.rfind("\n)");
  EXPECT_EQ(refusal(edited(files, 2, "\n98\n", "\n97\n")),
            "cav/owner:" + std::to_string(line_at(owner, close) ) + ": expected ')' after 97 owner labels, found '23'");
  EXPECT_EQ(refusal(edited(files, 2, "\n98\n(", "\n98{0}\n#")),
            "cav/owner:" + count_line + ": uniform lists 'N{value}' are not supported");
  const std::string& neighbour = text_of(files.neighbour);
  const std::size_t first = neighbour.find("\n(\n") + 3;
  EXPECT_EQ(refusal(edited(files, 3, "\n1\n", "\n0\n", first - 1)),
            "cav/neighbour:" + std::to_string(line_at(neighbour, first)) + ": face 0 has cell 0 on both sides");
  EXPECT_EQ(refusal(edited(files, 3, "\n1\n", "\n500\n", first - 1)),
            "cav/neighbour:" + std::to_string(line_at(neighbour, first)) +
                ": cell 500 out of range (owner and neighbour name 144 face sides, so at most 144 cells)");
  const std::string& boundary = text_of(files.boundary);
  EXPECT_EQ(refusal(edited(files, 4, "nFaces          24;", "nFaces          23;")),
            "cav/boundary:" + std::to_string(line_at(boundary, boundary.find("\n3\n") + 1)) +
                ": the patches end at face 97, but the mesh has 98 faces (each boundary face is in a patch)");
  EXPECT_EQ(refusal(edited(files, 4, "startFace       54;", "startFace       55;")),
            "cav/boundary:" + std::to_string(line_at(boundary, boundary.find("startFace       54;"))) +
                ": patch 'fixedWalls' starts at face 55, not at face 54 where the patch before it ends");
  EXPECT_EQ(refusal(edited(files, 0, "FoamFile", "FoamFil")),
            "cav/points:8: expected the FoamFile header, found 'FoamFil'");
  EXPECT_EQ(refusal(edited(files, 0, "(0 0 0)", "(0 0 nan)")),
            "cav/points:" + std::to_string(line_at(text_of(files.points), files.points->view().find("(0 0 0)"))) +
                ": expected coordinate 2 of point 0 (a finite number), found 'nan'");
}

TEST(FoamRefuse, CompactFaceOffsetsNameTheirLine) {
  const FoamFiles files = split_foam_bundle(slurp(kSeeds / "ascii_compact_2x1x1"));
  const std::string& faces = text_of(files.faces);
  const std::size_t eight = faces.find("\n4\n8\n") + 3;
  EXPECT_EQ(refusal(edited(files, 1, "\n4\n8\n", "\n4\n6\n")),
            "cav/faces:" + std::to_string(line_at(faces, eight)) + ": face 1 has 2 points (a face needs 3 or more)");
  EXPECT_EQ(refusal(edited(files, 1, "\n4\n8\n", "\n4\n2\n")),
            "cav/faces:" + std::to_string(line_at(faces, eight)) + ": face offset 2 is below the one before it");
}

TEST(FoamRefuse, BinaryErrorsNameTheFileAndByte) {
  const FoamFiles files = files_of(kVolume / "cavity_binary");
  const std::string& points = text_of(files.points);
  const std::size_t data = data_start(points, "60");
  FoamFiles cut = files;
  cut.points = shared(points.substr(0, data + 100));
  EXPECT_EQ(refusal(cut), "cav/points: byte " + std::to_string(data) +
                              ": truncated binary list: 60 points need 60 x 24 bytes and ')', 100 bytes are left");
  std::string owner = text_of(files.owner);
  const std::size_t labels = data_start(owner, "98");
  owner.replace(labels + 8, 4, std::string("\xff\xff\xff\xff", 4));
  FoamFiles bad = files;
  bad.owner = shared(owner);
  EXPECT_EQ(refusal(bad), "cav/owner: byte " + std::to_string(labels + 8) + ": label -1 is negative");
  std::string faces = text_of(files.faces);
  const std::size_t values = data_start(faces, "392");
  faces.replace(values + 4 * 5, 4, std::string("\x3c\0\0\0", 4));
  bad = files;
  bad.faces = shared(faces);
  EXPECT_EQ(refusal(bad),
            "cav/faces: byte " + std::to_string(values + 20) + ": label 60 out of range (the mesh has 60 points)");
  faces = text_of(files.faces);
  faces[values - 1 + 392 * 4 + 1] = ' ';
  bad.faces = shared(faces);
  EXPECT_EQ(refusal(bad), "cav/faces: byte " + std::to_string(values + 392 * 4) +
                              ": expected ')' after the binary data of 392 face point labels");
}

TEST(FoamRefuse, BundlesOfAnotherShape) {
  EXPECT_THROW(split_foam_bundle("short"), InputError);
  const std::string seed = slurp(kSeeds / "ascii_list_2x2x1");
  EXPECT_NO_THROW(split_foam_bundle(seed));
  EXPECT_THROW(split_foam_bundle(seed + "x"), InputError);
  EXPECT_THROW(split_foam_bundle(seed.substr(0, seed.size() - 1)), InputError);
  try {
    split_foam_bundle(std::string("\xff\0\0\0\0\0\0\0", 8));
    FAIL() << "accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), "foam bundle: byte 0: points has 255 bytes, but 0 are left");
  }
}

}  // namespace ffd
