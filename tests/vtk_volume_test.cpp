// VTU and legacy VTK volume readers: the points and cells meshio reads from the same
// files (test_data/volume/mixed_*, poly_*), exact write-back, moved nodes, refusals.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "common/errors.h"
#include "mesh/vtk_volume_io.h"

namespace ffd {
namespace {

std::string slurp(const std::string& name) {
  std::ifstream in(std::string(FFD_TEST_DATA) + "/volume/" + name, std::ios::binary);
  EXPECT_TRUE(in) << name;
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

bool is_vtu(const std::string& name) { return name.size() > 4 && name.substr(name.size() - 4) == ".vtu"; }

VolumeRead read_text(const std::string& text, const std::string& name) {
  auto bytes = std::make_shared<const FileBytes>(std::string(text));
  return is_vtu(name) ? read_vtu(bytes, name) : read_vtk_legacy(bytes, name);
}

std::string write_back(const VolumeRead& r, const Eigen::Matrix3Xd& positions) {
  std::ostringstream os;
  r.source.file->write(os, positions);
  return os.str();
}

// The mesh make_vtk.py writes (see test_data/volume/README.md), as meshio reads it back.
Eigen::Matrix3Xd expected_points(bool float32, bool ascii_vtu) {
  const double third = ascii_vtu ? 0.333333333333 : 1.0 / 3;  // meshio's ASCII VTU keeps 12 digits
  const double p[13][3] = {{0, 0, 0},       {1, 0, 0},         {1, 1, 0},        {0, 1, 0},     {0, 0, 1},
                           {1, 0, 1},       {1, 1, 1},         {0, 1, 1},        {0.5, 0.1, 1.7}, {0.5, 0.9, 1.7},
                           {2.25, 0.5, 0.5}, {third, -1.1, 0.2}, {0.7, -0.9, 1e-7}};
  Eigen::Matrix3Xd m(3, 13);
  for (int i = 0; i < 13; ++i)
    for (int k = 0; k < 3; ++k) m(k, i) = float32 ? static_cast<float>(p[i][k]) : p[i][k];
  return m;
}

void expect_mixed_cells(const VolumeCells& c) {
  const std::vector<std::uint8_t> types = {12, 13, 14, 10, 10};
  const std::vector<std::uint64_t> offsets = {0, 8, 14, 19, 23, 27};
  const std::vector<std::uint32_t> nodes = {0, 1, 2, 3, 4, 5, 6, 7, 4, 8, 5, 7, 9, 6, 1, 2, 6, 5, 10, 0, 1, 4, 11, 1, 5, 4, 12};
  EXPECT_EQ(c.type, types);
  EXPECT_EQ(c.offset, offsets);
  EXPECT_EQ(c.node, nodes);
  EXPECT_TRUE(c.face_offset.empty());
}

struct MixedFile {
  const char* name;
  bool float32;
  const char* encoding;
  const char* version;
};
constexpr MixedFile kMixed[] = {
    {"mixed_ascii.vtu", false, "ascii", "0.1"},
    {"mixed_binary.vtu", false, "binary", "0.1"},
    {"mixed_zlib32.vtu", true, "binary zlib", "0.1"},
    {"mixed_appended_raw.vtu", false, "appended raw", "1.0"},
    {"mixed_appended_zlib32.vtu", true, "appended raw zlib", "1.0"},
    {"mixed_appended_base64.vtu", false, "appended base64", "1.0"},
    {"mixed_appended_base64_zlib.vtu", false, "appended base64 zlib", "1.0"},
    {"mixed_ascii42.vtk", false, "ascii", "4.2"},
    {"mixed_binary42.vtk", true, "binary", "4.2"},
    {"mixed_ascii51.vtk", true, "ascii", "5.1"},
    {"mixed_binary51.vtk", false, "binary", "5.1"},
};

TEST(VtuVtkRead, MixedFilesGiveMeshiosPointsAndCells) {
  for (const MixedFile& m : kMixed) {
    SCOPED_TRACE(m.name);
    const VolumeRead r = read_text(slurp(m.name), m.name);
    const bool ascii_vtu = std::string(m.name) == "mixed_ascii.vtu";
    EXPECT_EQ(r.points, expected_points(m.float32, ascii_vtu));
    expect_mixed_cells(r.source.cells);
    EXPECT_EQ(r.source.encoding, m.encoding);
    EXPECT_EQ(r.source.version, m.version);
    EXPECT_EQ(r.source.format, is_vtu(m.name) ? VolumeFormat::Vtu : VolumeFormat::Vtk);
    EXPECT_TRUE(r.source.markers.empty());
  }
}

TEST(VtuVtkWrite, PositionsAsReadGiveTheSameBytes) {
  for (const MixedFile& m : kMixed) {
    SCOPED_TRACE(m.name);
    const std::string text = slurp(m.name);
    const VolumeRead r = read_text(text, m.name);
    EXPECT_EQ(write_back(r, r.points), text);
  }
}

// Moves nodes 2 and 11: the output reads back with the new positions (float32: rounded),
// the same cells, and the same bytes before the points and (uncompressed) after them.
TEST(VtuVtkWrite, MovedNodesReadBack) {
  for (const MixedFile& m : kMixed) {
    SCOPED_TRACE(m.name);
    const std::string text = slurp(m.name);
    const VolumeRead r = read_text(text, m.name);
    Eigen::Matrix3Xd moved = r.points;
    moved.col(2) += Eigen::Vector3d(0.125, -1.0 / 7, 3e-9);
    moved.col(11) = Eigen::Vector3d(-2.5, 1e10, 0.1);
    const std::string out = write_back(r, moved);
    const VolumeRead again = read_text(out, m.name);
    Eigen::Matrix3Xd expected = moved;
    if (m.float32) expected = moved.cast<float>().cast<double>();
    EXPECT_EQ(again.points, expected);
    expect_mixed_cells(again.source.cells);
    EXPECT_EQ(write_back(again, again.points), out);
    const std::size_t same_start = std::mismatch(text.begin(), text.end(), out.begin(), out.end()).first - text.begin();
    const std::size_t points_at = text.find(is_vtu(m.name) ? "<Points>" : "POINTS");
    if (std::string(m.encoding).find("appended") == std::string::npos) {
      EXPECT_GT(same_start, points_at);
    }
    const std::size_t tail = std::string(m.encoding).find("appended") != std::string::npos ? 20 : 200;
    EXPECT_EQ(out.substr(out.size() - std::min(tail, text.size())), text.substr(text.size() - std::min(tail, text.size())));
  }
}

TEST(VtuWrite, AsciiKeepsUnmovedNodesText) {
  const std::string text = slurp("mixed_ascii.vtu");
  const VolumeRead r = read_text(text, "mixed_ascii.vtu");
  Eigen::Matrix3Xd moved = r.points;
  moved(0, 12) = 0.75;
  const std::string out = write_back(r, moved);
  ASSERT_NE(text.find("7.00000000000e-01"), std::string::npos);
  EXPECT_EQ(out.find("7.00000000000e-01"), std::string::npos);  // node 12's x was the only 0.7
  EXPECT_NE(out.find("3.33333333333e-01"), std::string::npos);  // node 11 keeps its text
}

TEST(VtuWrite, AppendedOffsetsAfterThePointsShift) {
  const std::string text = slurp("mixed_appended_zlib32.vtu");
  const VolumeRead r = read_text(text, "mixed_appended_zlib32.vtu");
  Eigen::Matrix3Xd moved = r.points;
  moved.col(0) = Eigen::Vector3d(0.123456789, 9.87654321, -3.14159);
  const std::string out = write_back(r, moved);
  EXPECT_NE(out.size(), text.size());
  const VolumeRead again = read_text(out, "x.vtu");
  EXPECT_EQ(again.points.col(0), moved.col(0).cast<float>().cast<double>());
  // The cell data after the points still decodes: its zone values are the last array.
  EXPECT_EQ(out.substr(out.size() - 30), text.substr(text.size() - 30));
}

TEST(VtuRead, Polyhedron) {
  for (const char* name : {"poly_ascii.vtu", "poly_zlib.vtu"}) {
    SCOPED_TRACE(name);
    const VolumeRead r = read_text(slurp(name), name);
    ASSERT_EQ(r.source.cells.size(), 1u);
    EXPECT_EQ(r.source.cells.type[0], cell_type::kPolyhedron);
    EXPECT_EQ(r.source.cells.node, (std::vector<std::uint32_t>{0, 1, 2, 3, 4}));
    EXPECT_EQ(r.source.cells.face_offset, (std::vector<std::uint64_t>{0}));
    EXPECT_EQ(r.source.cells.face,
              (std::vector<std::uint32_t>{5, 4, 0, 3, 2, 1, 3, 0, 1, 4, 3, 1, 2, 4, 3, 2, 3, 4, 3, 3, 0, 4}));
    EXPECT_EQ(r.points(2, 4), 0.75);
  }
}

// A small ASCII VTU with one tet, edited by each refusal test.
const std::string kTet =
    "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\">\n"
    "<UnstructuredGrid><Piece NumberOfPoints=\"4\" NumberOfCells=\"1\">\n"
    "<Points><DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n"
    "0 0 0 1 0 0 0 1 0 0 0 1\n"
    "</DataArray></Points>\n"
    "<Cells>\n"
    "<DataArray type=\"Int32\" Name=\"connectivity\" format=\"ascii\">0 1 2 3</DataArray>\n"
    "<DataArray type=\"Int32\" Name=\"offsets\" format=\"ascii\">4</DataArray>\n"
    "<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">10</DataArray>\n"
    "</Cells></Piece></UnstructuredGrid></VTKFile>\n";

std::string error_of(const std::string& text, const std::string& name) {
  try {
    read_text(text, name);
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

std::string edited(std::string text, const std::string& from, const std::string& to) {
  const std::size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return text.replace(at, from.size(), to);
}

TEST(VtuRead, Refusals) {
  EXPECT_EQ(read_text(kTet, "t.vtu").source.cells.size(), 1u);
  EXPECT_EQ(error_of(edited(kTet, "0 1 2 3<", "0 1 2 7<"), "t.vtu"),
            "t.vtu:7: cell 0: node index 7 out of range (the file has 4 nodes)");
  EXPECT_EQ(error_of(edited(kTet, ">10<", ">99<"), "t.vtu"), "t.vtu:9: cell 0: unknown cell type 99");
  EXPECT_EQ(error_of(edited(kTet, ">10<", ">12<"), "t.vtu"), "t.vtu:9: cell 0: a hexahedron cell has 8 nodes, not 4");
  EXPECT_EQ(error_of(edited(kTet, "0 0 1\n", "0 0\n"), "t.vtu"),
            "t.vtu:5: the Points DataArray has 11 numbers where 12 (3 per node) are expected");
  EXPECT_EQ(error_of(edited(kTet, ">4<", ">5<"), "t.vtu"),
            "t.vtu:7: DataArray 'connectivity' is too short to hold 5 values");
  EXPECT_EQ(error_of(kTet.substr(0, 200), "t.vtu").substr(0, 30), "t.vtu:3: not well-formed XML: ");
  EXPECT_EQ(error_of(edited(kTet, "LittleEndian\"", "LittleEndian\" compressor=\"vtkLZ4DataCompressor\""), "t.vtu"),
            "t.vtu:1: compressor vtkLZ4DataCompressor is not supported; ffdtool reads zlib-compressed and uncompressed VTU");
  EXPECT_EQ(error_of(edited(kTet, "UnstructuredGrid\" v", "PolyData\" v"), "t.vtu"),
            "t.vtu:1: VTKFile type 'PolyData' is not a volume mesh; ffdtool reads VTK XML files of type UnstructuredGrid (.vtu)");
  EXPECT_EQ(error_of(edited(kTet, "</Piece>", "</Piece><Piece/>"), "t.vtu"),
            "t.vtu:10: a second Piece; ffdtool reads a VTU with one Piece");
}

TEST(VtuRead, BadBinaryData) {
  const std::string text = slurp("mixed_binary.vtu");
  const std::size_t points = text.find("format=\"binary\">", text.find("<Points>")) + 16;
  std::string bad = text;
  bad[points + 5] = '*';
  EXPECT_NE(error_of(bad, "b.vtu").find("b.vtu:8: DataArray 'Points' is not valid base64"), std::string::npos) << error_of(bad, "b.vtu");
  const std::string zlib = slurp("mixed_zlib32.vtu");
  const std::size_t at = zlib.find("format=\"binary\">", zlib.find("<Points>")) + 16 + 40;
  bad = zlib;
  bad[at] = bad[at] == 'A' ? 'B' : 'A';
  EXPECT_NE(error_of(bad, "z.vtu").find("is not valid zlib data"), std::string::npos) << error_of(bad, "z.vtu");
  const std::string raw = slurp("mixed_appended_raw.vtu");
  const std::string cut = error_of(raw.substr(0, raw.size() - 62) + "</AppendedData></VTKFile>", "r.vtu");
  EXPECT_EQ(cut, "r.vtu:17: DataArray 'types' is truncated: its header says 5 bytes, 1 follow") << cut;
  for (std::size_t cut = 0; cut < raw.size(); cut += 7) error_of(raw.substr(0, cut), "r.vtu");  // no crash
  for (std::size_t cut = 0; cut < zlib.size(); cut += 5) error_of(zlib.substr(0, cut), "z.vtu");
}

const std::string kLegacyTet =
    "# vtk DataFile Version 4.2\n"
    "a tet\n"
    "ASCII\n"
    "DATASET UNSTRUCTURED_GRID\n"
    "POINTS 4 double\n"
    "0 0 0 1 0 0\n"
    "0 1 0 0 0 1\n"
    "CELLS 1 5\n"
    "4 0 1 2 3\n"
    "CELL_TYPES 1\n"
    "10\n"
    "CELL_DATA 1\nSCALARS a int 1\nLOOKUP_TABLE default\n7\n";

TEST(VtkLegacyRead, Refusals) {
  const VolumeRead r = read_text(kLegacyTet, "t.vtk");
  EXPECT_EQ(r.source.cells.node, (std::vector<std::uint32_t>{0, 1, 2, 3}));
  EXPECT_EQ(error_of(edited(kLegacyTet, "4 0 1 2 3", "4 0 1 2 9"), "t.vtk"),
            "t.vtk:9: cell 0: node index 9 out of range (the file has 4 nodes)");
  EXPECT_EQ(error_of(edited(kLegacyTet, "\n10\n", "\n99\n"), "t.vtk"), "t.vtk:11: cell 0: unknown cell type 99");
  EXPECT_EQ(error_of(edited(kLegacyTet, "CELLS 1 5", "CELLS 1 6"), "t.vtk"), "t.vtk:10: 'CELL_TYPES' is not an integer");
  EXPECT_EQ(error_of(edited(kLegacyTet, "CELL_TYPES 1", "CELL_TYPES 2"), "t.vtk"),
            "t.vtk:10: CELL_TYPES has 2 cells where CELLS has 1");
  EXPECT_EQ(error_of(edited(kLegacyTet, "UNSTRUCTURED_GRID", "POLYDATA"), "t.vtk"),
            "t.vtk:4: DATASET POLYDATA is not supported; ffdtool reads legacy VTK files whose DATASET is UNSTRUCTURED_GRID");
  EXPECT_EQ(error_of(kLegacyTet.substr(0, 90), "t.vtk"), "t.vtk:5: the file is too short to hold 4 points");
  EXPECT_EQ(error_of(edited(kLegacyTet, "Version 4.2", "Version 6.0"), "t.vtk"),
            "t.vtk:1: legacy VTK version '6.0' is not supported (ffdtool reads 1.0 to 5.1)");
  const std::string binary = slurp("mixed_binary51.vtk");
  EXPECT_EQ(error_of(binary.substr(0, 200), "b.vtk"), "b.vtk: byte 102: the file is too short to hold 13 points");
  for (std::size_t cut = 0; cut < binary.size(); cut += 3) error_of(binary.substr(0, cut), "b.vtk");  // no crash
}

}  // namespace
}  // namespace ffd
