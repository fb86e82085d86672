// VTU arrays large enough to be read in parallel blocks (vtu_io.cpp's plain base64 path):
// the same cells, the same refusals with the same places, and the same bytes written back
// as when the base64 is broken into lines (the path that decodes it whole, one thread),
// for each header layout VTK and meshio write.
#include <gtest/gtest.h>

#include <cstring>
#include <sstream>
#include <string>
#include <vector>

#include "common/base64.h"
#include "common/errors.h"
#include "mesh/vtk_volume_io.h"

namespace ffd {
namespace {

// A strip of tetrahedra: cell c has nodes c, c+1, c+2, c+3.
struct Strip {
  std::vector<double> points;
  std::vector<std::int64_t> connectivity, offsets;
  std::vector<std::uint8_t> types;
};

Strip strip(std::size_t cells) {
  Strip s;
  for (std::size_t i = 0; i < cells + 3; ++i) s.points.insert(s.points.end(), {double(i), double(i % 2), double(i % 3)});
  for (std::size_t c = 0; c < cells; ++c) {
    for (std::int64_t k = 0; k < 4; ++k) s.connectivity.push_back(static_cast<std::int64_t>(c) + k);
    s.offsets.push_back(4 * static_cast<std::int64_t>(c + 1));
    s.types.push_back(10);
  }
  return s;
}

struct Layout {
  bool header_apart;  // VTK: the header encoded on its own; meshio: with the data
  bool header64;
  bool connectivity32;
  std::size_t wrap;  // 0: one line; else a line end every `wrap` characters
};

template <class T>
std::string bytes_of(const std::vector<T>& v) {
  std::string s(v.size() * sizeof(T), '\0');
  std::memcpy(s.data(), v.data(), s.size());
  return s;
}

std::string array_text(const std::string& data, const Layout& l) {
  std::string header(l.header64 ? 8 : 4, '\0');
  const std::uint64_t size = data.size();
  std::memcpy(header.data(), &size, header.size());  // little-endian, as declared
  std::string text;
  if (l.header_apart) {
    append_base64(header, text);
    append_base64(data, text);
  } else {
    append_base64(header + data, text);
  }
  if (l.wrap == 0) return text;
  std::string lines;
  for (std::size_t i = 0; i < text.size(); i += l.wrap) lines += text.substr(i, l.wrap) + "\n";
  return lines;
}

std::string data_array(const char* type, const char* name, int components, const std::string& data, const Layout& l) {
  return std::string("<DataArray type=\"") + type + "\" Name=\"" + name + "\" NumberOfComponents=\"" +
         std::to_string(components) + "\" format=\"binary\">\n" + array_text(data, l) + "\n</DataArray>\n";
}

std::string strip_vtu(const Strip& s, const Layout& l) {
  std::string connectivity;
  if (l.connectivity32) {
    const std::vector<std::int32_t> narrow(s.connectivity.begin(), s.connectivity.end());
    connectivity = data_array("Int32", "connectivity", 1, bytes_of(narrow), l);
  } else {
    connectivity = data_array("Int64", "connectivity", 1, bytes_of(s.connectivity), l);
  }
  return std::string("<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" "
                     "byte_order=\"LittleEndian\" header_type=\"") + (l.header64 ? "UInt64" : "UInt32") + "\">\n"
         "<UnstructuredGrid>\n<Piece NumberOfPoints=\"" + std::to_string(s.points.size() / 3) +
         "\" NumberOfCells=\"" + std::to_string(s.types.size()) + "\">\n<Points>\n" +
         data_array("Float64", "Points", 3, bytes_of(s.points), l) + "</Points>\n<Cells>\n" + connectivity +
         data_array("Int64", "offsets", 1, bytes_of(s.offsets), l) + data_array("UInt8", "types", 1, bytes_of(s.types), l) +
         "</Cells>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n";
}

VolumeRead read_strip(const std::string& text) {
  return read_vtu(std::make_shared<const FileBytes>(std::string(text)), "strip.vtu");
}

std::string strip_error(const std::string& text) {
  try {
    read_strip(text);
  } catch (const InputError& e) {
    return e.what();
  }
  return "read";
}

std::vector<Layout> layouts() {
  std::vector<Layout> all;
  for (bool apart : {true, false})
    for (bool header64 : {false, true})
      for (bool narrow : {false, true}) all.push_back({apart, header64, narrow, 0});
  return all;
}

constexpr std::size_t kCells = 70'000;  // 280,000 node indices: several blocks

TEST(VtuBlocks, CellsAsWrittenInEveryLayout) {
  const Strip s = strip(kCells);
  std::vector<std::uint64_t> offsets = {0};
  offsets.insert(offsets.end(), s.offsets.begin(), s.offsets.end());
  for (Layout l : layouts())
    for (std::size_t wrap : {std::size_t{0}, std::size_t{76}}) {
      l.wrap = wrap;
      SCOPED_TRACE(std::to_string(l.header_apart) + std::to_string(l.header64) + std::to_string(l.connectivity32) +
                   " wrap " + std::to_string(wrap));
      const std::string text = strip_vtu(s, l);
      const VolumeRead r = read_strip(text);
      EXPECT_EQ(r.source.cells.node, std::vector<std::uint32_t>(s.connectivity.begin(), s.connectivity.end()));
      EXPECT_EQ(r.source.cells.offset, offsets);
      EXPECT_EQ(r.source.cells.type, s.types);
      ASSERT_EQ(r.points.cols(), static_cast<Eigen::Index>(kCells + 3));
      EXPECT_EQ(r.points(0, 1234), 1234.0);
      std::ostringstream os;
      r.source.file->write(os, r.points);
      EXPECT_EQ(os.str(), text);
    }
}

// What a message says after its place (a wrapped file has its arrays on other lines).
std::string said(const std::string& message) { return message.substr(message.find(": ")); }

// The same message, naming the same cell, whether the array is read in blocks or decoded
// whole.
TEST(VtuBlocks, RefusalsNameTheSameCellAsTheWholeDecode) {
  Strip s = strip(kCells);
  s.connectivity[4 * 61'234 + 1] = 90'000'000;  // a node past the end, deep in a late block
  s.connectivity[4 * 65'000 + 2] = -1;          // and a later one
  for (Layout l : layouts()) {
    const std::string plain = strip_error(strip_vtu(s, l));
    EXPECT_EQ(plain, "strip.vtu:11: cell 61234: node index 90000000 out of range (the file has 70003 nodes)");
    l.wrap = 64;
    EXPECT_EQ(said(strip_error(strip_vtu(s, l))), said(plain));
  }
  Strip decreasing = strip(kCells);
  decreasing.offsets[50'001] = 4;
  EXPECT_EQ(strip_error(strip_vtu(decreasing, layouts()[0])), "strip.vtu:14: offsets decrease at cell 50001");
  EXPECT_EQ(said(strip_error(strip_vtu(decreasing, {true, false, false, 100}))), ": offsets decrease at cell 50001");
}

TEST(VtuBlocks, BadCharacterDeepInABlockIsPlaced) {
  const Strip s = strip(kCells);
  std::string text = strip_vtu(s, layouts()[0]);
  const std::size_t at = text.find("Name=\"connectivity\"");
  const std::size_t data = text.find('>', at) + 2;  // after the line end
  text[data + 1'000'003] = '#';
  EXPECT_EQ(strip_error(text), "strip.vtu:12: DataArray 'connectivity' is not valid base64");
}

}  // namespace
}  // namespace ffd
