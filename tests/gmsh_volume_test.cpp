// The Gmsh MSH reader (lib/mesh/gmsh_io.h): files made by gmsh 4.8 and meshio 7.0 read
// to what meshio reads from them (expected values computed with meshio, as FNV-1a
// checksums), writing back with the positions read gives the same bytes, moved nodes read
// back exactly, and every malformed input is refused with its place.
#include <gtest/gtest.h>

#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include "common/errors.h"
#include "mesh/gmsh_io.h"

namespace ffd {
namespace {

std::string read_data_file(const std::string& name) {
  std::ifstream in(std::string(FFD_TEST_DATA) + "/volume/" + name, std::ios::binary);
  EXPECT_TRUE(in) << name;
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

VolumeRead read_text(const std::string& text, const std::string& path = "t.msh") {
  return read_msh(std::make_shared<const FileBytes>(std::string(text)), path);
}

std::string write(const VolumeRead& read, const Eigen::Matrix3Xd& positions) {
  std::ostringstream out;
  read.source.file->write(out, positions);
  return out.str();
}

// FNV-1a over 64-bit values, as the expected values were computed (meshio, Python).
struct Fnv {
  std::uint64_t h = 14695981039346656037ull;
  void add(std::uint64_t v) {
    for (int i = 0; i < 8; ++i) {
      h ^= (v >> (8 * i)) & 0xff;
      h *= 1099511628211ull;
    }
  }
};

std::uint64_t points_hash(const Eigen::Matrix3Xd& p) {
  Fnv f;
  for (Eigen::Index i = 0; i < p.cols(); ++i)
    for (int k = 0; k < 3; ++k) {
      std::uint64_t bits;
      std::memcpy(&bits, &p(k, i), sizeof bits);
      f.add(bits);
    }
  return f.h;
}

// Hashed in meshio's order: meshio keeps Gmsh's corner order for a linear wedge, which is
// VTK's with corners 1 and 2, 4 and 5 swapped (the reader gives VTK's).
std::uint64_t cells_hash(const VolumeCells& cells) {
  static constexpr int kMeshioWedge[] = {0, 2, 1, 3, 5, 4};
  Fnv f;
  for (std::size_t c = 0; c < cells.size(); ++c) {
    f.add(cells.type[c]);
    const bool wedge = cells.type[c] == cell_type::kWedge;
    for (std::size_t j = 0; j < cells.degree(c); ++j) f.add(cells.nodes(c)[wedge ? kMeshioWedge[j] : j]);
  }
  return f.h;
}

struct ExpectedMarker {
  const char* name;
  int dimension;
  std::size_t count;
  std::uint64_t hash;
};

struct ExpectedFile {
  const char* name;
  Eigen::Index nodes;
  std::size_t cells;
  std::uint64_t points_hash, cells_hash;
  std::vector<ExpectedMarker> markers;
};

// meshio 7.0's reading of each file: points, cells (VTK types and order, tet10 reordered),
// and the physical groups from gmsh:physical and field_data, by (dimension, tag).
const std::vector<ExpectedFile>& expected_files() {
  static const std::vector<ExpectedFile> files = {
      {"box_hex_41_ascii.msh", 64, 45, 0xd2f0434ea7cc5b29ull, 0xa789a5d1affe6329ull,
       {{"bottom", 2, 9, 0x49614f10fb0856cdull}, {"top", 2, 9, 0x108843fe62b703acull},
        {"block", 3, 27, 0x9c14dbac483c22e8ull}}},
      {"box_tet10_22_bin.msh", 105, 82, 0x8026e85b6aab34e6ull, 0xa979686dfb5f323dull,
       {{"inlet", 2, 4, 0x64dbcbc3ab5bf1a5ull}, {"walls", 2, 32, 0x2dc7e819d09b9aa5ull},
        {"5", 2, 4, 0x2a0a6a1bf49360a5ull}, {"fluid", 3, 42, 0x6782e24e516f9b44ull}}},
      {"box_tet_22_ascii.msh", 38, 151, 0xa9f64de1b6f68031ull, 0x1e5b86e600febd2full,
       {{"inlet", 2, 8, 0xb0099f969b546f25ull}, {"walls", 2, 56, 0x1149069edf082125ull},
        {"5", 2, 8, 0x1936564b3387b325ull}, {"fluid", 3, 79, 0xe566bc0f34107812ull}}},
      {"box_tet_22_bin.msh", 22, 82, 0xb91132326c2b28f5ull, 0xc0ce75d4b14dc8c5ull,
       {{"inlet", 2, 4, 0x64dbcbc3ab5bf1a5ull}, {"walls", 2, 32, 0x2dc7e819d09b9aa5ull},
        {"5", 2, 4, 0x2a0a6a1bf49360a5ull}, {"fluid", 3, 42, 0x6782e24e516f9b44ull}}},
      {"box_tet_41_ascii.msh", 22, 82, 0xed5634111fa6580cull, 0xc0ce75d4b14dc8c5ull,
       {{"inlet", 2, 4, 0x64dbcbc3ab5bf1a5ull}, {"walls", 2, 32, 0x2dc7e819d09b9aa5ull},
        {"5", 2, 4, 0x2a0a6a1bf49360a5ull}, {"fluid", 3, 42, 0x6782e24e516f9b44ull}}},
      {"box_tet_41_bin.msh", 38, 151, 0xf9a4742b670616c1ull, 0x1e5b86e600febd2full,
       {{"inlet", 2, 8, 0xb0099f969b546f25ull}, {"walls", 2, 56, 0x1149069edf082125ull},
        {"5", 2, 8, 0x1936564b3387b325ull}, {"fluid", 3, 79, 0xe566bc0f34107812ull}}},
      {"meshio_hex_41_bin.msh", 64, 45, 0xd2f0434ea7cc5b29ull, 0xa789a5d1affe6329ull,
       {{"bottom", 2, 9, 0x49614f10fb0856cdull}, {"top", 2, 9, 0x108843fe62b703acull},
        {"block", 3, 27, 0x9c14dbac483c22e8ull}}},
      {"meshio_prism_22_ascii.msh", 30, 67, 0xe856ea6dc247526cull, 0x073e49f563e13566ull,
       {{"corner", 0, 1, 0xa8c7f832281a39c5ull}, {"edge", 1, 3, 0xda2bfb225e0d1f05ull},
        {"floor", 2, 9, 0x8060297efc3c1049ull}, {"layer", 3, 54, 0xec5eb783765c9baaull}}},
      {"prism_layer_22_bin.msh", 30, 67, 0xe856ea6dc247526cull, 0x073e49f563e13566ull,
       {{"corner", 0, 1, 0xa8c7f832281a39c5ull}, {"edge", 1, 3, 0xda2bfb225e0d1f05ull},
        {"floor", 2, 9, 0x8060297efc3c1049ull}, {"layer", 3, 54, 0xec5eb783765c9baaull}}},
      {"square_tri_41_ascii.msh", 30, 50, 0xb1d43d7ce88d585aull, 0xc8a91eda95aae60cull,
       {{"wall", 1, 8, 0xb0099f969b546f25ull}, {"domain", 2, 42, 0xa224880ed9d9a704ull}}},
      // gmsh -save_parametric: meshio refuses parametric nodes; the values are meshio's
      // reading of the same mesh saved without them.
      {"box_param_41_bin.msh", 22, 82, 0xb91132326c2b28f5ull, 0xc0ce75d4b14dc8c5ull,
       {{"inlet", 2, 4, 0x64dbcbc3ab5bf1a5ull}, {"walls", 2, 32, 0x2dc7e819d09b9aa5ull},
        {"5", 2, 4, 0x2a0a6a1bf49360a5ull}, {"fluid", 3, 42, 0x6782e24e516f9b44ull}}},
  };
  return files;
}

std::uint64_t indices_hash(const std::vector<std::uint64_t>& cells) {
  Fnv f;
  for (std::uint64_t c : cells) f.add(c);
  return f.h;
}

TEST(MshFiles, ReadAsMeshioReadsThem) {
  for (const ExpectedFile& file : expected_files()) {
    SCOPED_TRACE(file.name);
    const std::string name = file.name;
    const VolumeRead read = read_text(read_data_file(name), name);
    const VolumeSource& source = read.source;
    EXPECT_EQ(source.format, VolumeFormat::Msh);
    EXPECT_EQ(source.version, name.find("_41_") != std::string::npos ? "4.1" : "2.2");
    EXPECT_EQ(source.encoding, name.find("_bin") != std::string::npos ? "binary" : "ascii");
    EXPECT_EQ(source.dimension, name.find("square") == 0 ? 2 : 3);
    ASSERT_EQ(read.points.cols(), file.nodes);
    EXPECT_EQ(points_hash(read.points), file.points_hash);
    ASSERT_EQ(source.cells.size(), file.cells);
    EXPECT_EQ(cells_hash(source.cells), file.cells_hash);
    ASSERT_EQ(source.markers.size(), file.markers.size());
    for (std::size_t m = 0; m < file.markers.size(); ++m) {
      EXPECT_EQ(source.markers[m].name, file.markers[m].name);
      EXPECT_EQ(source.markers[m].dimension, file.markers[m].dimension);
      EXPECT_EQ(source.markers[m].cells.size(), file.markers[m].count);
      EXPECT_EQ(indices_hash(source.markers[m].cells), file.markers[m].hash);
    }
  }
}

// Every test file, including those meshio cannot read.
std::vector<std::string> all_files() {
  std::vector<std::string> names{"box_tet_part_41_bin.msh"};
  for (const ExpectedFile& file : expected_files()) names.push_back(file.name);
  return names;
}

// gmsh -part 2: the elements' entities are in $PartitionedEntities, with their groups;
// the partition interfaces are extra elements in entities that carry their parent's
// physical tag (here curves in (1, 4) and surfaces in (2, 7), groups no name is given to).
TEST(MshFiles, PartitionedEntitiesGiveTheGroups) {
  const VolumeRead read = read_text(read_data_file("box_tet_part_41_bin.msh"), "box_tet_part_41_bin.msh");
  EXPECT_EQ(read.points.cols(), 22);
  EXPECT_EQ(read.source.cells.size(), 94u);
  const std::vector<std::tuple<std::string, int, std::size_t>> expected = {
      {"4", 1, 7}, {"inlet", 2, 4}, {"walls", 2, 32}, {"5", 2, 4}, {"7", 2, 5}, {"fluid", 3, 42}};
  ASSERT_EQ(read.source.markers.size(), expected.size());
  for (std::size_t m = 0; m < expected.size(); ++m) {
    const VolumeMarker& marker = read.source.markers[m];
    EXPECT_EQ(std::tuple(marker.name, marker.dimension, marker.cells.size()), expected[m]);
    for (std::uint64_t c : marker.cells)
      EXPECT_EQ(cell_type_dimension(read.source.cells.type[c]), marker.dimension) << marker.name;
  }
}

TEST(MshFiles, WritingThePositionsReadGivesTheSameBytes) {
  for (const std::string& name : all_files()) {
    SCOPED_TRACE(name);
    const std::string bytes = read_data_file(name);
    const VolumeRead read = read_text(bytes, name);
    EXPECT_EQ(write(read, read.points), bytes);
  }
}

// Every other node moves (x, and z in 3D); the output reads back to exactly those
// positions with the same cells and markers, and keeps the file's length in binary.
TEST(MshFiles, MovedNodesReadBackExactly) {
  for (const std::string& name : all_files()) {
    SCOPED_TRACE(name);
    const std::string bytes = read_data_file(name);
    const VolumeRead read = read_text(bytes, name);
    Eigen::Matrix3Xd moved = read.points;
    for (Eigen::Index i = 0; i < moved.cols(); i += 2) {
      moved(0, i) += 0.1;
      if (read.source.dimension == 3) moved(2, i) = moved(2, i) * 1.5 - 1.0 / 3.0;
    }
    const std::string out = write(read, moved);
    const VolumeRead again = read_text(out, name);
    EXPECT_TRUE(again.points == moved);
    EXPECT_EQ(again.source.cells.type, read.source.cells.type);
    EXPECT_EQ(again.source.cells.node, read.source.cells.node);
    ASSERT_EQ(again.source.markers.size(), read.source.markers.size());
    for (std::size_t m = 0; m < read.source.markers.size(); ++m)
      EXPECT_EQ(again.source.markers[m].cells, read.source.markers[m].cells);
    if (read.source.encoding == "binary") {
      EXPECT_EQ(out.size(), bytes.size());
    }
  }
}

// ---- Inline files ----

// MSH 4.1 ASCII: sparse, unordered node tags (one above 2^32), two entities with named
// groups, a triangle and two tets.
const char* const kSparse41 =
    "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n"                                   // 1-3
    "$PhysicalNames\n2\n2 1 \"skin\"\n3 2 \"solid part\"\n$EndPhysicalNames\n"  // 4-8
    "$Entities\n0 0 1 1\n1 0 0 0 1 1 1 1 1 0\n1 0 0 0 1 1 1 1 2 1 1\n$EndEntities\n"  // 9-13
    "$Nodes\n2 5 3 1000000000000\n"                                             // 14-15
    "2 1 0 2\n900\n3\n0 0 0\n1 0 0\n"                                           // 16-20
    "3 1 0 3\n40\n7\n1000000000000\n0 1 0\n0 0 1\n1 1 1\n$EndNodes\n"            // 21-28
    "$Elements\n2 3 1 3\n"                                                      // 29-30
    "2 1 2 1\n1 900 3 40\n"                                                     // 31-32
    "3 1 4 2\n2 900 3 40 7\n3 3 40 7 1000000000000\n$EndElements\n";             // 33-36

std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const std::size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

TEST(MshInline, SparseTagsMapToFileOrder) {
  const VolumeRead read = read_text(kSparse41);
  ASSERT_EQ(read.points.cols(), 5);
  EXPECT_EQ(read.points.col(4), Eigen::Vector3d(1, 1, 1));
  const VolumeCells& cells = read.source.cells;
  ASSERT_EQ(cells.size(), 3u);
  EXPECT_EQ(cells.type, (std::vector<std::uint8_t>{cell_type::kTriangle, cell_type::kTetra, cell_type::kTetra}));
  EXPECT_EQ(cells.node, (std::vector<std::uint32_t>{0, 1, 2, 0, 1, 2, 3, 1, 2, 3, 4}));
  ASSERT_EQ(read.source.markers.size(), 2u);
  EXPECT_EQ(read.source.markers[0].name, "skin");
  EXPECT_EQ(read.source.markers[0].dimension, 2);
  EXPECT_EQ(read.source.markers[0].cells, (std::vector<std::uint64_t>{0}));
  EXPECT_EQ(read.source.markers[1].name, "solid part");
  EXPECT_EQ(read.source.markers[1].cells, (std::vector<std::uint64_t>{1, 2}));
  EXPECT_EQ(read.source.dimension, 3);
}

TEST(MshInline, TextKeepsTagsAndOtherSectionsAndRewritesOnlyMovedNodes) {
  const std::string text = std::string("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Comments\n$Nodes is not here\n"
                                       "$EndComments\n$Nodes\n3\n1 0.10 0 0\n2 1 0 0\n3 0 1.0e0 0\n$EndNodes\n"
                                       "$Elements\n1\n1 2 2 0 1 1 2 3\n$EndElements\n"
                                       "$NodeData\n1\n\"u\"\n0\n3\n0\n1\n3\n1 5\n2 6\n3 7\n$EndNodeData\n");
  const VolumeRead read = read_text(text);
  EXPECT_EQ(read.source.dimension, 2);
  EXPECT_TRUE(read.source.markers.empty());  // physical tag 0: no group
  Eigen::Matrix3Xd moved = read.points;
  moved(1, 2) = 0.5;
  EXPECT_EQ(write(read, moved), replaced(text, "3 0 1.0e0 0\n", "3 0 0.5 0\n"));
}

// Gmsh's tet10 numbers its last two edge nodes (3,2) and (3,1); VTK's (1,3) and (2,3).
TEST(MshInline, QuadraticTetraTakesVtkOrder) {
  const std::string text =
      "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n10\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n5 .5 0 0\n"
      "6 .5 .5 0\n7 0 .5 0\n8 0 0 .5\n9 0 .5 .5\n10 .5 0 .5\n$EndNodes\n"
      "$Elements\n2\n1 11 2 6 1 1 2 3 4 5 6 7 8 9 10\n2 15 2 0 1 1\n$EndElements\n";
  const VolumeRead read = read_text(text);
  const VolumeCells& cells = read.source.cells;
  ASSERT_EQ(cells.size(), 2u);
  EXPECT_EQ(cells.type[0], cell_type::kQuadraticTetra);
  EXPECT_EQ(std::vector<std::uint32_t>(cells.nodes(0), cells.nodes(0) + 10),
            (std::vector<std::uint32_t>{0, 1, 2, 3, 4, 5, 6, 7, 9, 8}));
  EXPECT_EQ(cells.type[1], cell_type::kVertex);
  ASSERT_EQ(read.source.markers.size(), 1u);
  EXPECT_EQ(read.source.markers[0].name, "6");
  EXPECT_EQ(read.source.markers[0].dimension, 3);
  EXPECT_EQ(read.source.markers[0].cells, (std::vector<std::uint64_t>{0}));
}

TEST(MshInline, GmshKindsWithoutVtkNumberAreCarried) {
  // A 9-node triangle (Gmsh 20) has no VTK kind: kOtherCell with its nodes as Gmsh has them.
  std::string nodes;
  for (int i = 1; i <= 9; ++i) nodes += std::to_string(i) + " " + std::to_string(i) + " 0 0\n";
  const VolumeRead read = read_text("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n9\n" + nodes +
                                    "$EndNodes\n$Elements\n1\n7 20 0 9 8 7 6 5 4 3 2 1\n$EndElements\n");
  ASSERT_EQ(read.source.cells.size(), 1u);
  EXPECT_EQ(read.source.cells.type[0], cell_type::kOtherCell);
  EXPECT_EQ(read.source.cells.node, (std::vector<std::uint32_t>{8, 7, 6, 5, 4, 3, 2, 1, 0}));
}

// ---- Binary, both byte orders ----

struct BinaryWriter {
  bool big = false;
  std::string out;
  template <class T>
  void put(T value) {
    char b[sizeof value];
    std::memcpy(b, &value, sizeof value);
    if (big != (__BYTE_ORDER__ == __ORDER_BIG_ENDIAN__)) std::reverse(b, b + sizeof value);
    out.append(b, sizeof value);
  }
};

// MSH 4.1 binary with size_t of `size` bytes: one node block (tags 10, 20, 30, 40), one tet.
std::string binary41(bool big, int size = 8) {
  BinaryWriter w{big, "$MeshFormat\n4.1 1 " + std::to_string(size) + "\n"};
  const auto put_size = [&](std::uint64_t v) { size == 8 ? w.put(v) : w.put(static_cast<std::uint32_t>(v)); };
  w.put<std::int32_t>(1);
  w.out += "\n$EndMeshFormat\n$Nodes\n";
  for (std::uint64_t v : {1, 4, 10, 40}) put_size(v);
  w.put<std::int32_t>(3), w.put<std::int32_t>(1), w.put<std::int32_t>(0), put_size(4);
  for (std::uint64_t tag : {10, 20, 30, 40}) put_size(tag);
  for (double x : {0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0}) w.put(x);
  w.out += "\n$EndNodes\n$Elements\n";
  for (std::uint64_t v : {1, 1, 1, 1}) put_size(v);
  w.put<std::int32_t>(3), w.put<std::int32_t>(1), w.put<std::int32_t>(4), put_size(1);
  for (std::uint64_t v : {1, 40, 30, 20, 10}) put_size(v);
  w.out += "\n$EndElements\n";
  return w.out;
}

// MSH 2.2 binary: nodes 10, 20, 30, 40 as (int, 3 doubles) records; a run of one tet with
// two tags (physical 5, elementary 1), then a run of one triangle with one tag (0: none).
std::string binary22(bool big) {
  BinaryWriter w{big, "$MeshFormat\n2.2 1 8\n"};
  w.put<std::int32_t>(1);
  w.out += "\n$EndMeshFormat\n$Nodes\n4\n";
  for (int i = 0; i < 4; ++i) {
    w.put<std::int32_t>(10 * (i + 1));
    for (int k = 0; k < 3; ++k) w.put(i == k + 1 ? 1.0 : 0.0);
  }
  w.out += "\n$EndNodes\n$Elements\n2\n";
  for (std::int32_t v : {4, 1, 2, 7, 5, 1, 10, 20, 30, 40}) w.put(v);
  for (std::int32_t v : {2, 1, 1, 8, 0, 40, 30, 20}) w.put(v);
  w.out += "\n$EndElements\n";
  return w.out;
}

TEST(MshBinary, BothByteOrdersReadAndWriteBack) {
  for (const std::string& bytes : {binary41(false), binary41(true), binary41(false, 4), binary41(true, 4),
                                   binary22(false), binary22(true)}) {
    SCOPED_TRACE(bytes.substr(12, 8));
    const VolumeRead read = read_text(bytes);
    ASSERT_EQ(read.points.cols(), 4);
    EXPECT_EQ(read.points.col(3), Eigen::Vector3d(0, 0, 1));
    EXPECT_EQ(read.source.encoding, "binary");
    EXPECT_EQ(write(read, read.points), bytes);
    Eigen::Matrix3Xd moved = read.points;
    moved(2, 3) = 2.5;
    const std::string out = write(read, moved);
    EXPECT_EQ(out.size(), bytes.size());
    EXPECT_TRUE(read_text(out).points == moved);
  }
  EXPECT_EQ(read_text(binary41(true)).source.cells.node, (std::vector<std::uint32_t>{3, 2, 1, 0}));
  const VolumeRead v2 = read_text(binary22(true));
  EXPECT_EQ(v2.source.cells.type, (std::vector<std::uint8_t>{cell_type::kTetra, cell_type::kTriangle}));
  EXPECT_EQ(v2.source.cells.node, (std::vector<std::uint32_t>{0, 1, 2, 3, 3, 2, 1}));
  ASSERT_EQ(v2.source.markers.size(), 1u);
  EXPECT_EQ(v2.source.markers[0].name, "5");
  EXPECT_EQ(v2.source.markers[0].cells, (std::vector<std::uint64_t>{0}));
}

// ---- Refusals, each with its place ----

void expect_refused(const std::string& text, const std::string& what) {
  try {
    read_text(text);
    ADD_FAILURE() << "accepted; expected: " << what;
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), what);
  }
}

TEST(MshRefusals, TextErrorsNameTheLine) {
  const std::string s = kSparse41;
  expect_refused(replaced(s, "2 900 3 40 7", "2 900 3 40 99"),
                 "t.msh:34: element 2 names node 99, which $Nodes does not list");
  expect_refused(replaced(s, "3 1 4 2", "3 1 77 2"), "t.msh:33: element type 77 is not a Gmsh element type");
  expect_refused(replaced(s, "3 1 4 2", "3 1 34 2"),
                 "t.msh:33: element type 34 has no fixed node count (polygons, polyhedra and XFEM elements are "
                 "not read)");
  expect_refused(replaced(s, "2 5 3 1000000000000", "2 6 3 1000000000000"),
                 "t.msh:15: $Nodes promises 6 nodes, its blocks hold 5");
  expect_refused(replaced(s, "2 3 1 3\n", "2 4 1 3\n"), "t.msh:30: $Elements promises 4 elements, its blocks hold 3");
  expect_refused(replaced(s, "1 1 1\n$EndNodes\n", "1 1 1\n"), "t.msh:28: expected $EndNodes, found '$Elements'");
  // Truncated: a block promising more than the rest can hold, or a file ending mid-record.
  expect_refused(s.substr(0, s.find("2 900 3 40 7") + 5),
                 "t.msh:33: the file promises 2 elements in the block, more than its remaining 6 bytes can hold");
  expect_refused(s.substr(0, s.find("1 1 1\n$EndNodes") + 3), "t.msh:27: the file ends where a coordinate should be");
  expect_refused(replaced(s, "2 5 3 1000000000000", "2 99999999999 3 1000000000000"),
                 "t.msh:15: the file promises 99999999999 nodes, more than its remaining 176 bytes can hold");
  expect_refused(replaced(s, "3 1 4 2", "3 9 4 2"),
                 "t.msh:33: an element block names entity 9 of dimension 3, which $Entities does not list");
  expect_refused(replaced(s, "\n7\n", "\n900\n"), "t.msh:14: node tag 900 appears twice in $Nodes");
  expect_refused(replaced(s, "0 1 0\n", "0 nan 0\n"), "t.msh:25: a coordinate 'nan' is not a finite number");
  expect_refused(replaced(s, "4.1 0 8", "4.0 0 8"), "t.msh:2: MSH version '4.0' is not read (versions 4.1 and 2.2 are)");
  expect_refused(replaced(s, "$EndEntities\n", "$EndEntities\n$Comments\n"),
                 "t.msh:14: section $Comments has no $EndComments");
}

TEST(MshRefusals, TwoPointTwoErrors) {
  const std::string s = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n2\n1 0 0 0\n2 1 0 0\n$EndNodes\n"
                        "$Elements\n1\n1 1 2 0 1 1 2\n$EndElements\n";
  EXPECT_NO_THROW(read_text(s));
  expect_refused(replaced(s, "1 1 2 0 1 1 2", "1 1 2 0 1 1 3"), "t.msh:11: element 1 names node 3, which $Nodes does not list");
  expect_refused(replaced(s, "2 1 0 0", "0 1 0 0"), "t.msh:4: node tag 0 in $Nodes (Gmsh's tags start at 1)");
  expect_refused(replaced(s, "$Elements\n1\n", "$Elements\n2\n"), "t.msh:12: expected an element tag (a non-negative integer), found '$EndElements'");
  expect_refused(s.substr(0, s.find("$Elements")), "t.msh:9: the file has no $Elements section");
  expect_refused(replaced(s, "1 1 2 0 1 1 2", "1 1 -2 0 1 1 2"), "t.msh:11: expected the number of tags (a non-negative integer), found '-2'");
  const std::string elements = s.substr(s.find("$Elements"));
  expect_refused(replaced(s, "$Nodes", elements + "$Nodes"), "t.msh:4: $Elements comes before $Nodes");
  expect_refused(s + elements, "t.msh:13: a second $Elements section");
  expect_refused(replaced(s, "2.2 0 8", "2.2 0 4"), "t.msh:2: data size 4 is not read (8 is)");
}

TEST(MshRefusals, BinaryErrorsNameTheByte) {
  const std::string bytes = binary41(false);
  const std::size_t coordinates = bytes.find("$Nodes\n") + 7 + 4 * 8 + 3 * 4 + 8 + 4 * 8;
  const std::size_t header = bytes.find("$Nodes\n") + 7 + 3 * 8;  // the node count's last header value
  expect_refused(bytes.substr(0, coordinates + 40),
                 "t.msh: byte " + std::to_string(header) + ": the file promises 4 nodes, more than its remaining " +
                     std::to_string(coordinates + 40 - header - 8) + " bytes can hold");
  expect_refused(bytes.substr(0, bytes.find("\n$EndElements")),
                 "t.msh: byte " + std::to_string(bytes.find("\n$EndElements")) +
                     ": the file ends where $EndElements should be");
  std::string bad_marker = bytes;
  bad_marker[bytes.find("8\n") + 2] = 2;
  expect_refused(bad_marker, "t.msh:3: the binary byte-order marker is not the int 1");
  std::string run = binary22(false);
  run[run.find("$Elements\n2\n") + 12 + 4] = 3;  // the first run claims 3 of the 2 elements
  expect_refused(run, "t.msh: byte " + std::to_string(run.find("$Elements\n2\n") + 12 + 4) +
                          ": a run of 3 elements, where 2 of the $Elements count remain");
  std::string unknown = bytes;
  const std::size_t last_node = unknown.size() - std::string("\n$EndElements\n").size() - 8;
  unknown[last_node] = 11;  // node tag 10 -> 11
  expect_refused(unknown, "t.msh: byte " + std::to_string(last_node - 32) +
                              ": element 1 names node 11, which $Nodes does not list");
}

}  // namespace
}  // namespace ffd
