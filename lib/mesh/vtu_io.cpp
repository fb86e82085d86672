// The VTK XML UnstructuredGrid reader (read_vtu) and its VolumeFile for encoded points.
//
// The file is split before any XML parser sees it: raw appended data (after the '_' of
// <AppendedData>) is not XML. The part before it, closed by "</AppendedData></VTKFile>",
// is cut to its skeleton (mesh/xml_skeleton.h: the tags, with each long text cut after
// its first character) and parsed in place by pugixml with no encoding conversion, so
// every text and attribute value pugixml returns maps back to its offset in the file:
// the Points text, the base64 runs and the appended offset="..." values are located in
// the file's bytes.
// (pugixml over expat: a DOM whose values are offsets into our own buffer, which
// expat's callbacks would make us track by hand.)
#include <pugixml.hpp>
#include <zlib.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <charconv>
#include <cmath>
#include <cstring>
#include <functional>
#include <limits>
#include <optional>
#include <ostream>

#include "common/base64.h"
#include "common/errors.h"
#include "common/numbers.h"
#include "mesh/volume_patch.h"
#include "mesh/vtk_volume_io.h"
#include "mesh/xml_skeleton.h"

namespace ffd {
namespace {

constexpr std::size_t kNone = std::string_view::npos;

enum class Scalar : std::uint8_t { Int8, UInt8, Int16, UInt16, Int32, UInt32, Int64, UInt64, Float32, Float64 };

struct ScalarName {
  std::string_view name;
  Scalar type;
  std::size_t size;
};
constexpr ScalarName kScalars[] = {
    {"Int8", Scalar::Int8, 1},     {"UInt8", Scalar::UInt8, 1},   {"Int16", Scalar::Int16, 2},
    {"UInt16", Scalar::UInt16, 2}, {"Int32", Scalar::Int32, 4},   {"UInt32", Scalar::UInt32, 4},
    {"Int64", Scalar::Int64, 8},   {"UInt64", Scalar::UInt64, 8}, {"Float32", Scalar::Float32, 4},
    {"Float64", Scalar::Float64, 8}};

std::size_t scalar_size(Scalar t) { return kScalars[static_cast<int>(t)].size; }
std::string_view scalar_name(Scalar t) { return kScalars[static_cast<int>(t)].name; }
bool is_float(Scalar t) { return t == Scalar::Float32 || t == Scalar::Float64; }

// An integer of type t at `at`; a UInt64 above int64's range reads as its maximum, which
// every range check refuses.
std::int64_t load_integer(const char* at, Scalar t, bool swap) {
  switch (t) {
    case Scalar::Int8: return load_bytes<std::int8_t>(at, false);
    case Scalar::UInt8: return load_bytes<std::uint8_t>(at, false);
    case Scalar::Int16: return load_bytes<std::int16_t>(at, swap);
    case Scalar::UInt16: return load_bytes<std::uint16_t>(at, swap);
    case Scalar::Int32: return load_bytes<std::int32_t>(at, swap);
    case Scalar::UInt32: return load_bytes<std::uint32_t>(at, swap);
    case Scalar::Int64: return load_bytes<std::int64_t>(at, swap);
    default: {
      const std::uint64_t v = load_bytes<std::uint64_t>(at, swap);
      return v > static_cast<std::uint64_t>(INT64_MAX) ? INT64_MAX : static_cast<std::int64_t>(v);
    }
  }
}

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; }

// ---- the file -----------------------------------------------------------------------

// How the file stores binary arrays (VTKFile's attributes).
struct Layout {
  bool swap = false;       // byte_order differs from this machine's
  bool big_endian = false;
  std::size_t header_size = 4;  // header_type UInt32 or UInt64
  bool zlib = false;
};

// An appended DataArray's offset="N": its value and where the value's text is.
struct AppendedOffset {
  std::uint64_t value = 0;
  std::size_t begin = 0, end = 0;
};

enum class Format { Ascii, Binary, Appended };

// A DataArray element as declared.
struct DataArray {
  std::string name;
  Scalar type = Scalar::Float32;
  std::uint64_t components = 1;
  Format format = Format::Ascii;
  std::size_t begin = 0, end = 0;  // its text, or appended: its bytes up to where they may end
  std::size_t at = 0;              // the element's first byte, for its line
};

struct Vtu {
  Vtu(std::string_view b, const std::string& p) : bytes(b), path(p) {}
  std::string_view bytes;
  const std::string& path;
  XmlSkeleton xml;  // the XML part's skeleton, parsed in place
  pugi::xml_document doc;
  Layout layout;
  std::size_t appended = kNone;  // the first byte after AppendedData's '_'
  std::size_t appended_end = 0;  // where its data ends ("</AppendedData>" or the last non-space)
  bool appended_base64 = false;
  std::vector<AppendedOffset> offsets;  // of every appended DataArray, in file order
};

std::string line_place(const Vtu& f, std::size_t offset) {
  offset = std::min(offset, f.bytes.size());
  if (f.appended != kNone && offset >= f.appended && !f.appended_base64)
    return f.path + ": byte " + std::to_string(offset);
  const auto lines = std::count(f.bytes.begin(), f.bytes.begin() + static_cast<std::ptrdiff_t>(offset), '\n');
  return f.path + ":" + std::to_string(lines + 1);
}

[[noreturn]] void fail(const Vtu& f, std::size_t offset, const std::string& message) {
  throw InputError(At{line_place(f, offset)}, message);
}

std::string quoted(const DataArray& a) { return "DataArray '" + a.name + "'"; }

std::size_t node_offset(const Vtu& f, pugi::xml_node node) {
  const std::ptrdiff_t at = node.offset_debug();
  return at < 0 ? 0 : f.xml.text_offset(static_cast<std::size_t>(at));
}

// Where a value pugixml returns lies in the file, or kNone for one outside the buffer.
std::size_t value_offset(const Vtu& f, const char* value) {
  const char* base = f.xml.markup.data();
  if (value < base || value >= base + f.xml.markup.size()) return kNone;
  return f.xml.text_offset(static_cast<std::size_t>(value - base));
}

// Cuts the raw or base64 appended data off the XML part and notes where it is.
void split_appended(Vtu& f) {
  const std::string_view b = f.bytes;
  const std::size_t tag = b.find("<AppendedData");
  if (tag == kNone) {
    f.xml = xml_skeleton(b);
    return;
  }
  const std::size_t tag_end = b.find('>', tag);
  if (tag_end == kNone) fail(f, tag, "the AppendedData tag is not closed");
  std::size_t underscore = tag_end + 1;
  while (underscore < b.size() && is_space(b[underscore])) ++underscore;
  if (underscore >= b.size() || b[underscore] != '_' || b[tag_end - 1] == '/')
    fail(f, tag_end, "AppendedData's data must start with '_'");
  f.appended = underscore + 1;
  f.appended_end = b.rfind("</AppendedData>");
  if (f.appended_end == kNone || f.appended_end < f.appended)
    fail(f, f.appended, "the AppendedData element is not closed (no '</AppendedData>' after its data)");
  f.xml = xml_skeleton(b.substr(0, underscore));
  f.xml.markup += "</AppendedData></VTKFile>";
}

// pugixml leaves text and attribute values as the file has them (no end-of-line or entity
// conversion): the array texts are the file's bytes at their own offsets, which the
// writer patches, and a large array is skipped at memchr speed instead of rewritten.
constexpr unsigned kParseFlags = pugi::parse_minimal | pugi::parse_cdata;

void parse_xml(Vtu& f) {
  const pugi::xml_parse_result r =
      f.doc.load_buffer_inplace(f.xml.markup.data(), f.xml.markup.size(), kParseFlags, pugi::encoding_utf8);
  if (!r) fail(f, f.xml.text_offset(static_cast<std::size_t>(std::max<std::ptrdiff_t>(r.offset, 0))),
               std::string("not well-formed XML: ") + r.description());
}

// VTKFile's type, byte order, header type and compressor.
pugi::xml_node read_root(Vtu& f, std::string& version) {
  const pugi::xml_node root = f.doc.document_element();
  if (std::string_view(root.name()) != "VTKFile")
    fail(f, node_offset(f, root), "not a VTK XML file (the root element is not VTKFile)");
  const std::string_view type = root.attribute("type").value();
  if (type != "UnstructuredGrid")
    fail(f, node_offset(f, root), "VTKFile type '" + std::string(type) +
         "' is not a volume mesh; ffdtool reads VTK XML files of type UnstructuredGrid (.vtu)");
  version = root.attribute("version").value();
  const std::string_view order = root.attribute("byte_order").value();
  if (order != "" && order != "LittleEndian" && order != "BigEndian")
    fail(f, node_offset(f, root), "unknown byte_order '" + std::string(order) + "'");
  f.layout.big_endian = order == "BigEndian";
  f.layout.swap = f.layout.big_endian != (__BYTE_ORDER__ == __ORDER_BIG_ENDIAN__);
  const std::string_view header = root.attribute("header_type").value();
  if (header != "" && header != "UInt32" && header != "UInt64")
    fail(f, node_offset(f, root), "header_type '" + std::string(header) + "' is not UInt32 or UInt64");
  f.layout.header_size = header == "UInt64" ? 8 : 4;
  const std::string_view compressor = root.attribute("compressor").value();
  if (compressor != "" && compressor != "vtkZLibDataCompressor")
    fail(f, node_offset(f, root), "compressor " + std::string(compressor) +
         " is not supported; ffdtool reads zlib-compressed and uncompressed VTU");
  f.layout.zlib = !compressor.empty();
  return root;
}

// The one Piece of the UnstructuredGrid.
pugi::xml_node find_piece(const Vtu& f, pugi::xml_node root) {
  const pugi::xml_node grid = root.child("UnstructuredGrid");
  if (!grid) fail(f, node_offset(f, root), "VTKFile has no UnstructuredGrid element");
  const pugi::xml_node piece = grid.child("Piece");
  if (!piece) fail(f, node_offset(f, grid), "the UnstructuredGrid has no Piece");
  if (const pugi::xml_node second = piece.next_sibling("Piece"))
    fail(f, node_offset(f, second), "a second Piece; ffdtool reads a VTU with one Piece");
  return piece;
}

// Notes every appended DataArray's offset attribute, for finding where a base64 array
// ends and for shifting later offsets when the Points array changes size.
void collect_offsets(Vtu& f) {
  struct Walker : pugi::xml_tree_walker {
    Vtu* f;
    bool for_each(pugi::xml_node& node) override {
      if (std::string_view(node.name()) != "DataArray" || std::string_view(node.attribute("format").value()) != "appended")
        return true;
      const pugi::xml_attribute a = node.attribute("offset");
      long long value;
      const std::size_t begin = value_offset(*f, a.value());
      if (!a || begin == kNone || begin == 0 || !parse_integer(a.value(), value) || value < 0)
        fail(*f, node_offset(*f, node), "an appended DataArray needs offset=\"N\" with N >= 0");
      const std::size_t end = f->bytes.find(f->bytes[begin - 1], begin);
      f->offsets.push_back({static_cast<std::uint64_t>(value), begin, end == kNone ? begin : end});
      return true;
    }
  } walker;
  walker.f = &f;
  f.doc.traverse(walker);
}

// Where appended data starting at `begin` may end: raw data at AppendedData's end, base64
// text at the next array's offset.
std::size_t appended_limit(const Vtu& f, std::uint64_t offset) {
  if (!f.appended_base64) return f.appended_end;
  std::uint64_t next = f.appended_end - f.appended;
  for (const AppendedOffset& o : f.offsets)
    if (o.value > offset) next = std::min(next, o.value);
  return f.appended + static_cast<std::size_t>(next);
}

// The text span of a DataArray (ascii, binary): its one text child, found in the file.
void text_span(const Vtu& f, pugi::xml_node node, DataArray& a) {
  a.begin = a.end = a.at;
  const pugi::xml_node text = node.first_child();
  if (!text) return;
  const std::size_t begin = value_offset(f, text.value());
  if (text.type() != pugi::node_pcdata || text.next_sibling() || begin == kNone)
    fail(f, a.at, quoted(a) + " must hold text only");
  a.begin = begin;
  a.end = std::min(f.bytes.find('<', begin), f.bytes.size());
}

void appended_span(const Vtu& f, pugi::xml_node node, DataArray& a) {
  if (f.appended == kNone) fail(f, a.at, quoted(a) + " is appended but the file has no AppendedData");
  long long offset = 0;
  parse_integer(node.attribute("offset").value(), offset);  // checked by collect_offsets
  if (static_cast<std::uint64_t>(offset) > f.appended_end - f.appended)
    fail(f, a.at, quoted(a) + " has offset " + std::to_string(offset) + ", past the end of the AppendedData");
  a.begin = f.appended + static_cast<std::size_t>(offset);
  a.end = appended_limit(f, static_cast<std::uint64_t>(offset));
}

DataArray declare(const Vtu& f, pugi::xml_node node) {
  DataArray a;
  a.name = node.attribute("Name").value();
  a.at = node_offset(f, node);
  const std::string_view type = node.attribute("type").value();
  const auto* s = std::find_if(std::begin(kScalars), std::end(kScalars), [&](const ScalarName& n) { return n.name == type; });
  if (s == std::end(kScalars)) fail(f, a.at, quoted(a) + " has unknown type '" + std::string(type) + "'");
  a.type = s->type;
  long long components = 1;
  if (node.attribute("NumberOfComponents") &&
      (!parse_integer(node.attribute("NumberOfComponents").value(), components) || components < 1 || components > 1000000))
    fail(f, a.at, quoted(a) + "'s NumberOfComponents is not a count");
  a.components = static_cast<std::uint64_t>(components);
  const std::string_view format = node.attribute("format").value();
  if (format == "ascii") a.format = Format::Ascii;
  else if (format == "binary") a.format = Format::Binary;
  else if (format == "appended") a.format = Format::Appended;
  else fail(f, a.at, quoted(a) + " has format '" + std::string(format) + "' (expected ascii, binary or appended)");
  if (a.format == Format::Appended)
    appended_span(f, node, a);
  else
    text_span(f, node, a);
  return a;
}

// ---- binary arrays ------------------------------------------------------------------

// An array's values as decoded from base64 and zlib, and how they were encoded.
struct Stored {
  DecodedBytes decoded;       // base64's bytes (header included)
  std::string inflated;       // zlib's values
  bool from_file = false;     // values lie in the file (raw appended, uncompressed)
  bool in_decoded = false;    // values lie in `decoded` (base64, uncompressed)
  std::size_t first = 0, size = 0;                  // the values within the file or `decoded`
  std::size_t encoded_begin = 0, encoded_end = 0;   // the array's encoded bytes in the file
  std::uint64_t blocks = 0, block_size = 0, last_block_size = 0;  // zlib's header
  bool header_apart = false;  // base64: the header was encoded on its own (padded)

  std::string_view values(std::string_view file) const {
    if (from_file) return file.substr(first, size);
    if (in_decoded) return decoded.view().substr(first, size);
    return inflated;
  }
};

std::uint64_t header_number(std::string_view s, std::size_t i, const Layout& l) {
  const char* at = s.data() + i * l.header_size;
  return l.header_size == 8 ? load_bytes<std::uint64_t>(at, l.swap) : load_bytes<std::uint32_t>(at, l.swap);
}

// One zlib block: where its packed bytes are in the array, and where its bytes go.
struct ZlibBlock {
  std::size_t at = 0, packed = 0;
  std::uint64_t first = 0, size = 0;
};

// The blocks the header in `s` declares, up to the first that the data cannot hold;
// `problem` says what is wrong with that one (empty when all are well).
std::vector<ZlibBlock> zlib_blocks(const Vtu& f, const DataArray& a, std::string_view s, const Stored& st,
                                   std::string& problem) {
  const std::size_t h = f.layout.header_size;
  std::vector<ZlibBlock> blocks;
  blocks.reserve(static_cast<std::size_t>(st.blocks));
  std::size_t at = (3 + st.blocks) * h;
  std::uint64_t total = 0;  // uncompressed bytes
  for (std::uint64_t k = 0; k < st.blocks; ++k) {
    const std::uint64_t size = k + 1 == st.blocks && st.last_block_size ? st.last_block_size : st.block_size;
    const std::uint64_t packed = header_number(s, 3 + k, f.layout);
    if (packed > s.size() - at) {
      problem = quoted(a) + ": zlib block " + std::to_string(k) + " is truncated";
      break;
    }
    if (size > packed * 1032 + 64) {  // deflate's largest ratio is 1032:1
      problem = quoted(a) + ": zlib block " + std::to_string(k) + " cannot hold " + std::to_string(size) + " bytes";
      break;
    }
    blocks.push_back({at, static_cast<std::size_t>(packed), total, size});
    at += packed;
    total += size;
  }
  return blocks;
}

// zlib blocks after their header in `s`: inflated into st.inflated, the blocks on every
// thread (VTK compresses each on its own); returns the bytes used. The first problem in
// file order is the one reported.
std::size_t inflate_blocks(const Vtu& f, const DataArray& a, std::string_view s, Stored& st) {
  const std::size_t h = f.layout.header_size;
  if (s.size() < 3 * h) fail(f, a.at, quoted(a) + "'s compression header is truncated");
  st.blocks = header_number(s, 0, f.layout);
  st.block_size = header_number(s, 1, f.layout);
  st.last_block_size = header_number(s, 2, f.layout);
  if (st.blocks > (s.size() - 3 * h) / h) fail(f, a.at, quoted(a) + "'s compression header is truncated");
  if (st.block_size > (1u << 30) || st.last_block_size > st.block_size)
    fail(f, a.at, quoted(a) + "'s compression header has a block size out of range");
  std::string problem;
  const std::vector<ZlibBlock> blocks = zlib_blocks(f, a, s, st, problem);
  st.inflated.resize(blocks.empty() ? 0 : blocks.back().first + blocks.back().size);
  std::vector<char> bad(blocks.size(), 0);
#pragma omp parallel for schedule(dynamic, 8)
  for (std::int64_t k = 0; k < static_cast<std::int64_t>(blocks.size()); ++k) {
    const ZlibBlock& b = blocks[static_cast<std::size_t>(k)];
    uLongf out = static_cast<uLongf>(b.size);
    bad[static_cast<std::size_t>(k)] = uncompress(reinterpret_cast<Bytef*>(st.inflated.data() + b.first), &out,
                                                  reinterpret_cast<const Bytef*>(s.data() + b.at),
                                                  static_cast<uLong>(b.packed)) != Z_OK || out != b.size;
  }
  for (std::size_t k = 0; k < blocks.size(); ++k)
    if (bad[k])
      fail(f, a.at, quoted(a) + ": zlib block " + std::to_string(k) + " is not valid zlib data of " +
           std::to_string(blocks[k].size) + " bytes");
  if (!problem.empty()) fail(f, a.at, problem);
  return blocks.empty() ? (3 + st.blocks) * h : blocks.back().at + blocks.back().packed;
}

// The header and values in `s` (raw or decoded): notes where the values are; returns the
// bytes used.
std::size_t unpack(const Vtu& f, const DataArray& a, std::string_view s, Stored& st) {
  if (f.layout.zlib) return inflate_blocks(f, a, s, st);
  const std::size_t h = f.layout.header_size;
  if (s.size() < h) fail(f, a.at, quoted(a) + "'s header is truncated");
  const std::uint64_t size = header_number(s, 0, f.layout);
  if (size > s.size() - h)
    fail(f, a.at, quoted(a) + " is truncated: its header says " + std::to_string(size) + " bytes, " +
         std::to_string(s.size() - h) + " follow");
  st.first = h;
  st.size = static_cast<std::size_t>(size);
  return h + st.size;
}

// A base64 array's text without the spaces around it.
std::string_view base64_text(const Vtu& f, const DataArray& a) {
  std::string_view text = f.bytes.substr(a.begin, a.end - a.begin);
  while (!text.empty() && is_space(text.front())) text.remove_prefix(1);
  while (!text.empty() && is_space(text.back())) text.remove_suffix(1);
  return text;
}

// Decodes a binary or appended array.
Stored decode(const Vtu& f, const DataArray& a) {
  Stored st;
  std::string_view text = f.bytes.substr(a.begin, a.end - a.begin);
  if (a.format == Format::Appended && !f.appended_base64) {
    const std::size_t used = unpack(f, a, text, st);
    st.from_file = !f.layout.zlib;
    st.first += a.begin;
    st.encoded_begin = a.begin;
    st.encoded_end = a.begin + used;
    return st;
  }
  text = base64_text(f, a);
  st.encoded_begin = static_cast<std::size_t>(text.data() - f.bytes.data());
  st.encoded_end = st.encoded_begin + text.size();
  const std::size_t bad = decode_base64(text, st.decoded);
  if (bad != kNone) fail(f, st.encoded_begin + bad, quoted(a) + " is not valid base64");
  const std::size_t used = unpack(f, a, st.decoded.view(), st);
  if (used != st.decoded.size)
    fail(f, a.at, quoted(a) + " has " + std::to_string(st.decoded.size - used) + " bytes after its data");
  st.in_decoded = !f.layout.zlib;
  const std::size_t header = f.layout.zlib ? (3 + st.blocks) * f.layout.header_size : f.layout.header_size;
  const std::size_t chars = (header + 2) / 3 * 4;
  st.header_apart = header % 3 != 0 && text.size() >= chars && text[chars - 1] == '=';
  return st;
}

// ---- integer arrays -----------------------------------------------------------------

using RangeMessage = std::function<std::string(std::uint64_t index, long long value)>;

std::uint64_t max_values(const DataArray& a) {
  const std::size_t text = a.end - a.begin;
  return a.format == Format::Ascii ? text / 2 + 1 : std::numeric_limits<std::uint64_t>::max();
}

template <class T>
void read_ascii_integers(const Vtu& f, const DataArray& a, std::uint64_t count, long long lo, long long hi,
                         std::vector<T>& out, const RangeMessage& range) {
  const char* p = f.bytes.data() + a.begin;
  const char* end = f.bytes.data() + a.end;
  for (std::uint64_t i = 0;; ++i) {
    while (p < end && is_space(*p)) ++p;
    if (i == count) {
      if (p != end) fail(f, static_cast<std::size_t>(p - f.bytes.data()), quoted(a) + " has more than " + std::to_string(count) + " values");
      return;
    }
    const std::size_t at = static_cast<std::size_t>(p - f.bytes.data());
    if (p == end) fail(f, at, quoted(a) + " has " + std::to_string(i) + " values where " + std::to_string(count) + " are expected");
    long long v;
    const auto [next, ec] = std::from_chars(p, end, v);
    if (ec != std::errc() || (next < end && !is_space(*next)))
      fail(f, at, quoted(a) + ": '" + std::string(p, std::find_if(p, end, is_space)) + "' is not an integer");
    if (v < lo || v > hi) fail(f, at, range(i, v));
    out.push_back(static_cast<T>(v));
    p = next;
  }
}

// A base64 array (uncompressed) whose text is plain: whole groups, no space, padding only
// after a header encoded apart and in the last group. The values are then decoded block
// by block, in parallel, straight into their destination: no copy of the decoded array.
struct PlainBase64 {
  std::string_view groups;           // the text holding the values (and a joined header)
  std::size_t lead = 0;              // decoded bytes before the first value
  std::uint64_t bytes = 0;           // the values' bytes, as the header says
  std::array<char, 3> last{};        // the last group, decoded
  std::size_t last_size = 0;
};

std::optional<PlainBase64> plain_base64(const Vtu& f, const DataArray& a) {
  const std::string_view text = base64_text(f, a);
  const std::size_t h = f.layout.header_size, chars = (h + 2) / 3 * 4;
  if (text.size() < chars + 4 || text.size() % 4 != 0) return std::nullopt;
  PlainBase64 p;
  const bool apart = text[chars - 1] == '=';
  DecodedBytes header;
  if (decode_base64(text.substr(0, chars), header) != kNone || header.size < h) return std::nullopt;
  p.groups = apart ? text.substr(chars) : text;
  p.lead = apart ? 0 : h;
  p.bytes = h == 8 ? load_bytes<std::uint64_t>(header.data.get(), f.layout.swap)
                   : load_bytes<std::uint32_t>(header.data.get(), f.layout.swap);
  DecodedBytes last;
  if (decode_base64(p.groups.substr(p.groups.size() - 4), last) != kNone || last.size == 0) return std::nullopt;
  std::copy(last.data.get(), last.data.get() + last.size, p.last.begin());
  p.last_size = last.size;
  if (3 * (p.groups.size() / 4 - 1) + p.last_size != p.lead + p.bytes) return std::nullopt;
  return p;
}

// The first value of a block out of range.
struct BadValue {
  std::uint64_t index = UINT64_MAX;
  long long value = 0;
};

// Decodes and checks values [k0, k1) of a plain array into out[k0, k1); returns false if a
// group is not plain, and notes in `bad` the first value out of [lo, hi].
template <class T>
bool read_plain_block(const Vtu& f, const DataArray& a, const PlainBase64& p, std::uint64_t k0, std::uint64_t k1,
                      long long lo, long long hi, std::vector<char>& local, T* out, BadValue& bad) {
  const std::size_t size = scalar_size(a.type), groups = p.groups.size() / 4;
  const std::size_t start = p.lead + k0 * size, end = p.lead + k1 * size;
  const std::size_t g0 = start / 3, g1 = (end + 2) / 3;  // the groups holding them
  const std::size_t whole = std::min(g1, groups - 1) - g0;
  local.resize(3 * (g1 - g0));
  if (decode_base64_groups(p.groups.data() + 4 * g0, whole, local.data()) != whole) return false;
  if (g1 == groups) std::copy(p.last.begin(), p.last.begin() + p.last_size, local.begin() + 3 * whole);
  const char* v = local.data() + (start - 3 * g0);
  for (std::uint64_t k = k0; k < k1; ++k, v += size) {
    const std::int64_t x = load_integer(v, a.type, f.layout.swap);
    if (x < lo || x > hi) {
      bad = {k, x};
      return true;
    }
    out[k] = static_cast<T>(x);
  }
  return true;
}

// Reads `count` values of a plain array into out[0, count) on every thread, in fixed
// blocks. Returns false if the text is not plain after all (the caller decodes it the
// general way, which says where it is wrong); fails on the first value out of range.
template <class T>
bool read_plain_integers(const Vtu& f, const DataArray& a, const PlainBase64& p, std::uint64_t count, long long lo,
                         long long hi, T* out, const RangeMessage& range) {
  constexpr std::uint64_t kBlock = 3 << 14;  // values
  const std::int64_t blocks = static_cast<std::int64_t>((count + kBlock - 1) / kBlock);
  std::vector<BadValue> bad(static_cast<std::size_t>(blocks));
  std::atomic<bool> plain{true};
#pragma omp parallel
  {
    std::vector<char> local;
#pragma omp for schedule(static)
    for (std::int64_t b = 0; b < blocks; ++b) {
      const std::uint64_t k0 = static_cast<std::uint64_t>(b) * kBlock, k1 = std::min(count, k0 + kBlock);
      if (!read_plain_block(f, a, p, k0, k1, lo, hi, local, out, bad[static_cast<std::size_t>(b)])) plain = false;
    }
  }
  if (!plain) return false;
  for (const BadValue& b : bad)
    if (b.index != UINT64_MAX) fail(f, a.at, range(b.index, b.value));
  return true;
}

// Appends `count` integers of `a` to `out`, each in [lo, hi] (else the message `range`
// makes).
template <class T>
void read_integers(const Vtu& f, const DataArray& a, std::uint64_t count, long long lo, long long hi,
                   std::vector<T>& out, const RangeMessage& range) {
  if (is_float(a.type)) fail(f, a.at, quoted(a) + " has type " + std::string(scalar_name(a.type)) + "; expected an integer type");
  if (count > max_values(a))
    fail(f, a.at, quoted(a) + " is too short to hold " + std::to_string(count) + " values");
  const std::size_t base = out.size(), size = scalar_size(a.type);
  if (a.format == Format::Ascii) {
    out.reserve(base + count);
    return read_ascii_integers(f, a, count, lo, hi, out, range);
  }
  if (!f.layout.zlib && (a.format == Format::Binary || f.appended_base64))
    if (const std::optional<PlainBase64> p = plain_base64(f, a); p && p->bytes == count * size) {
      out.resize(base + count);
      if (read_plain_integers(f, a, *p, count, lo, hi, out.data() + base, range)) return;
      out.resize(base);
    }
  const Stored st = decode(f, a);
  const std::string_view v = st.values(f.bytes);
  if (v.size() / size != count || v.size() % size != 0)
    fail(f, a.at, quoted(a) + " holds " + std::to_string(v.size()) + " bytes where " + std::to_string(count) + " values of " +
         std::string(scalar_name(a.type)) + " are expected");
  out.resize(base + count);
  for (std::uint64_t i = 0; i < count; ++i) {
    const std::int64_t x = load_integer(v.data() + i * size, a.type, f.layout.swap);
    if (x < lo || x > hi) fail(f, a.at, range(i, x));
    out[base + i] = static_cast<T>(x);
  }
}

// ---- points -------------------------------------------------------------------------

struct PointsRead {
  Eigen::Matrix3Xd points;
  std::vector<std::uint64_t> spans;  // ascii: each node's text
  Stored stored;                     // binary
};

void read_ascii_points(const Vtu& f, const DataArray& a, std::uint64_t n, PointsRead& r) {
  if (3 * n > max_values(a)) fail(f, a.at, "the Points DataArray is too short to hold " + std::to_string(n) + " nodes");
  r.points.resize(3, static_cast<Eigen::Index>(n));
  r.spans.resize(2 * n);
  const char* p = f.bytes.data() + a.begin;
  const char* end = f.bytes.data() + a.end;
  for (std::uint64_t i = 0; i < 3 * n; ++i) {
    while (p < end && is_space(*p)) ++p;
    const std::size_t at = static_cast<std::size_t>(p - f.bytes.data());
    if (p == end) fail(f, at, "the Points DataArray has " + std::to_string(i) + " numbers where " + std::to_string(3 * n) + " (3 per node) are expected");
    double x;
    const auto [next, ec] = std::from_chars(p, end, x);
    if (ec != std::errc() || (next < end && !is_space(*next)) || !std::isfinite(x))
      fail(f, at, "node " + std::to_string(i / 3) + ": '" + std::string(p, std::find_if(p, end, is_space)) + "' is not a finite number");
    if (a.type == Scalar::Float32) x = static_cast<float>(x);
    r.points(static_cast<Eigen::Index>(i % 3), static_cast<Eigen::Index>(i / 3)) = x;
    if (i % 3 == 0) r.spans[2 * (i / 3)] = at;
    if (i % 3 == 2) r.spans[2 * (i / 3) + 1] = static_cast<std::size_t>(next - f.bytes.data());
    p = next;
  }
  while (p < end && is_space(*p)) ++p;
  if (p != end) fail(f, static_cast<std::size_t>(p - f.bytes.data()), "the Points DataArray has more than " + std::to_string(n) + " nodes");
}

PointsRead read_points(const Vtu& f, const DataArray& a, std::uint64_t n) {
  if (!is_float(a.type))
    fail(f, a.at, "Points of type " + std::string(scalar_name(a.type)) + " are not supported; ffdtool reads Float32 and Float64 points");
  if (a.components != 3) fail(f, a.at, "Points need NumberOfComponents=\"3\", not " + std::to_string(a.components));
  PointsRead r;
  if (a.format == Format::Ascii) {
    read_ascii_points(f, a, n, r);
    return r;
  }
  r.stored = decode(f, a);
  const std::string_view v = r.stored.values(f.bytes);
  const BinaryScalar scalar{a.type == Scalar::Float64, f.layout.big_endian};
  const std::size_t size = scalar_size(a.type);
  if (v.size() != n * 3 * size)
    fail(f, a.at, "the Points DataArray holds " + std::to_string(v.size()) + " bytes where " + std::to_string(n) +
         " nodes take " + std::to_string(n * 3 * size));
  r.points.resize(3, static_cast<Eigen::Index>(n));
  for (std::uint64_t i = 0; i < 3 * n; ++i) {
    const double x = read_binary_scalar(v.data() + i * size, scalar);
    if (!std::isfinite(x)) fail(f, a.at, "node " + std::to_string(i / 3) + " has a coordinate that is not finite");
    r.points(static_cast<Eigen::Index>(i % 3), static_cast<Eigen::Index>(i / 3)) = x;
  }
  return r;
}

// ---- cells --------------------------------------------------------------------------

struct CellArrays {
  std::optional<DataArray> connectivity, offsets, types, faces, faceoffsets;
};

CellArrays find_cell_arrays(const Vtu& f, pugi::xml_node piece) {
  CellArrays c;
  const pugi::xml_node cells = piece.child("Cells");
  for (pugi::xml_node node : cells.children("DataArray")) {
    DataArray a = declare(f, node);
    std::optional<DataArray>* slot = a.name == "connectivity" ? &c.connectivity
                                     : a.name == "offsets"    ? &c.offsets
                                     : a.name == "types"      ? &c.types
                                     : a.name == "faces"      ? &c.faces
                                     : a.name == "faceoffsets" ? &c.faceoffsets
                                                               : nullptr;
    if (!slot) fail(f, a.at, "Cells " + quoted(a) + " is not supported (ffdtool reads connectivity, offsets, types, faces, faceoffsets)");
    if (*slot) fail(f, a.at, "a second Cells " + quoted(a));
    *slot = std::move(a);
  }
  return c;
}

const DataArray& need(const Vtu& f, const std::optional<DataArray>& a, const char* name, pugi::xml_node piece) {
  if (!a) fail(f, node_offset(f, piece), std::string("the Piece has cells but no Cells DataArray '") + name + "'");
  return *a;
}

// Each cell's type and node count, checked.
void check_cells(const Vtu& f, const CellArrays& arrays, const VolumeCells& cells) {
  for (std::size_t c = 0; c < cells.size(); ++c) {
    if (!vtk_cell_fits(cells.type[c], cells.degree(c)))
      fail(f, arrays.types->at, "cell " + std::to_string(c) + ": " + vtk_cell_problem(cells.type[c], cells.degree(c)));
  }
}

// What is wrong with face[start, end) as one polyhedron's stream (its face count, then
// each face's node count and nodes below `nodes`), or an empty string.
std::string stream_problem(const std::vector<std::uint32_t>& face, std::uint64_t start, std::uint64_t end,
                           std::uint64_t nodes) {
  if (start >= end) return "a polyhedron without faces";
  std::uint64_t j = start + 1, k = 0;
  for (; k < face[start] && j < end; ++k) {
    const std::uint64_t first = j + 1, last = j + 1 + face[j];
    if (last > end) break;
    for (std::uint64_t m = first; m < last; ++m)
      if (face[m] >= nodes)
        return "node index " + std::to_string(face[m]) + " out of range (the file has " + std::to_string(nodes) + " nodes)";
    j = last;
  }
  if (k != face[start] || j != end) return "the face stream does not match its face and node counts";
  return {};
}

// Polyhedra's face streams: faceoffsets (end offsets, -1 for other kinds) and faces.
void read_faces(const Vtu& f, const CellArrays& arrays, std::uint64_t nodes, VolumeCells& cells) {
  const std::size_t n = cells.size();
  const bool any = std::find(cells.type.begin(), cells.type.end(), cell_type::kPolyhedron) != cells.type.end();
  if (!any && !arrays.faces) return;
  if (!arrays.faces || !arrays.faceoffsets) fail(f, arrays.types->at, "polyhedron cells need the Cells DataArrays faces and faceoffsets");
  std::vector<std::int64_t> ends;
  read_integers(f, *arrays.faceoffsets, n, -1, INT64_MAX / 2, ends,
                [](std::uint64_t i, long long v) { return "faceoffsets value " + std::to_string(v) + " of cell " + std::to_string(i) + " is out of range"; });
  std::int64_t total = 0;
  for (std::size_t c = 0; c < n; ++c) {
    if ((ends[c] >= 0) != (cells.type[c] == cell_type::kPolyhedron))
      fail(f, arrays.faceoffsets->at, "cell " + std::to_string(c) + " is a " + cell_type_name(cells.type[c]) +
           (ends[c] >= 0 ? " with faces" : " without faces (faceoffsets -1)"));
    if (ends[c] >= 0 && ends[c] < total) fail(f, arrays.faceoffsets->at, "faceoffsets decrease at cell " + std::to_string(c));
    total = std::max(total, ends[c]);
  }
  read_integers(f, *arrays.faces, static_cast<std::uint64_t>(total), 0, UINT32_MAX, cells.face,
                [](std::uint64_t i, long long v) { return "faces value " + std::to_string(i) + " (" + std::to_string(v) + ") is out of range"; });
  cells.face_offset.assign(n, 0);
  std::uint64_t start = 0;
  for (std::size_t c = 0; c < n; ++c) {
    cells.face_offset[c] = start;
    if (ends[c] < 0) continue;
    const std::uint64_t end = static_cast<std::uint64_t>(ends[c]);
    const std::string problem = stream_problem(cells.face, start, end, nodes);
    if (!problem.empty()) fail(f, arrays.faces->at, "cell " + std::to_string(c) + ": " + problem);
    start = end;
  }
}

VolumeCells read_cells(const Vtu& f, pugi::xml_node piece, std::uint64_t ncells, std::uint64_t nodes) {
  VolumeCells cells;
  const CellArrays arrays = find_cell_arrays(f, piece);
  if (ncells == 0) return cells;
  const DataArray& offsets = need(f, arrays.offsets, "offsets", piece);
  cells.offset.reserve(ncells + 1);  // after its 0: the file's end offsets
  read_integers(f, offsets, ncells, 0, INT64_MAX / 2, cells.offset,
                [](std::uint64_t i, long long v) { return "offset " + std::to_string(v) + " of cell " + std::to_string(i) + " is negative"; });
  for (std::size_t c = 1; c < ncells; ++c)
    if (cells.offset[c + 1] < cells.offset[c]) fail(f, offsets.at, "offsets decrease at cell " + std::to_string(c));
  read_integers(f, need(f, arrays.connectivity, "connectivity", piece), cells.offset.back(), 0,
                static_cast<long long>(nodes) - 1, cells.node, [&](std::uint64_t i, long long v) {
                  const auto c = std::upper_bound(cells.offset.begin(), cells.offset.end(), i) - cells.offset.begin() - 1;
                  return "cell " + std::to_string(c) + ": node index " + std::to_string(v) + " out of range (the file has " +
                         std::to_string(nodes) + " nodes)";
                });
  read_integers(f, need(f, arrays.types, "types", piece), ncells, 0, 255, cells.type,
                [](std::uint64_t i, long long v) { return "cell " + std::to_string(i) + ": unknown cell type " + std::to_string(v); });
  check_cells(f, arrays, cells);
  read_faces(f, arrays, nodes, cells);
  return cells;
}

// ---- writing ------------------------------------------------------------------------

// How the Points array of a VTU is encoded when it is base64 or zlib: written back by
// re-encoding that array only, and only when a node moved.
struct PointsEncoding {
  Layout layout;
  bool base64 = false;
  bool header_apart = false;
  bool float32 = false;
  std::uint64_t blocks = 0, block_size = 0, last_block_size = 0;
  std::size_t begin = 0, end = 0;        // the encoded array in the file
  std::vector<AppendedOffset> later;     // offsets of appended arrays after it, in file order
};

class EncodedVtuPoints final : public VolumeFile {
public:
  EncodedVtuPoints(SharedBytes bytes, PointsEncoding encoding, std::string values)
      : bytes_(std::move(bytes)), e_(std::move(encoding)), values_(std::move(values)) {}

  void write(std::ostream& os, const Eigen::Matrix3Xd& positions) const override {
    std::string values = values_;
    if (!patch(values, positions)) {
      os.write(bytes_->data(), static_cast<std::streamsize>(bytes_->size()));
      return;
    }
    const std::string encoded = encode(values);
    const std::int64_t delta = static_cast<std::int64_t>(encoded.size()) - static_cast<std::int64_t>(e_.end - e_.begin);
    // Streamed: the file's bytes between the edits go out as they are, without a copy.
    const auto bytes = [&](std::size_t from, std::size_t to) {
      os.write(bytes_->data() + from, static_cast<std::streamsize>(to - from));
    };
    std::size_t kept = 0;  // bytes_[kept, ...) is not yet written
    for (const AppendedOffset& o : e_.later) {
      bytes(kept, o.begin);
      os << static_cast<std::int64_t>(o.value) + delta;
      kept = o.end;
    }
    bytes(kept, e_.begin);
    os.write(encoded.data(), static_cast<std::streamsize>(encoded.size()));
    bytes(e_.end, bytes_->size());
  }

private:
  // Writes the moved nodes into `values`; false if none moved.
  bool patch(std::string& values, const Eigen::Matrix3Xd& positions) const {
    const BinaryScalar scalar{!e_.float32, e_.layout.big_endian};
    const std::size_t size = e_.float32 ? 4 : 8;
    bool moved = false;
    for (Eigen::Index i = 0; i < positions.cols(); ++i) {
      char* at = values.data() + static_cast<std::size_t>(i) * 3 * size;
      const Eigen::Vector3d stored(read_binary_scalar(at, scalar), read_binary_scalar(at + size, scalar),
                                   read_binary_scalar(at + 2 * size, scalar));
      if (unmoved(positions.col(i), stored, e_.float32)) continue;
      for (int k = 0; k < 3; ++k) write_binary_scalar(at + k * size, positions(k, i), scalar);
      moved = true;
    }
    return moved;
  }

  void put_number(std::string& out, std::uint64_t x) const {
    char b[8];
    if (e_.layout.header_size == 8)
      store_bytes<std::uint64_t>(b, x, e_.layout.swap);
    else
      store_bytes<std::uint32_t>(b, static_cast<std::uint32_t>(x), e_.layout.swap);
    out.append(b, e_.layout.header_size);
  }

  // The header and data of the array as the file encodes them.
  std::string encode(const std::string& values) const {
    std::string header, data;
    if (!e_.layout.zlib) {
      put_number(header, values.size());
      data = values;
    } else {
      put_number(header, e_.blocks);
      put_number(header, e_.block_size);
      put_number(header, e_.last_block_size);
      std::vector<std::string> blocks(static_cast<std::size_t>(e_.blocks));
#pragma omp parallel for schedule(dynamic, 8)
      for (std::int64_t k = 0; k < static_cast<std::int64_t>(e_.blocks); ++k) {  // each block on its own
        const std::size_t first = static_cast<std::size_t>(k) * static_cast<std::size_t>(e_.block_size);
        const std::size_t size = std::min<std::size_t>(static_cast<std::size_t>(e_.block_size), values.size() - first);
        std::string& block = blocks[static_cast<std::size_t>(k)];
        uLongf packed = compressBound(static_cast<uLong>(size));
        block.resize(packed);
        compress2(reinterpret_cast<Bytef*>(block.data()), &packed, reinterpret_cast<const Bytef*>(values.data() + first),
                  static_cast<uLong>(size), Z_DEFAULT_COMPRESSION);
        block.resize(packed);
      }
      for (const std::string& block : blocks) {
        put_number(header, block.size());
        data += block;
      }
    }
    if (!e_.base64) return header + data;
    std::string text;
    if (e_.header_apart) {
      append_base64(header, text);
      append_base64(data, text);
    } else {
      append_base64(header + data, text);
    }
    return text;
  }

  SharedBytes bytes_;
  PointsEncoding e_;
  std::string values_;
};

std::shared_ptr<const VolumeFile> points_file(const Vtu& f, SharedBytes bytes, const DataArray& a, PointsRead& r) {
  if (a.format == Format::Ascii) return std::make_shared<TextPoints>(std::move(bytes), std::move(r.spans), 3, r.points);
  const BinaryScalar scalar{a.type == Scalar::Float64, f.layout.big_endian};
  if (r.stored.from_file) {
    const std::uint64_t stride = 3 * scalar_size(a.type);
    return std::make_shared<BinaryPoints>(std::move(bytes), std::vector<BinaryBlock>{{0, static_cast<std::uint64_t>(r.points.cols()), r.stored.first, stride}},
                                          scalar, 3);
  }
  PointsEncoding e;
  e.layout = f.layout;
  e.base64 = a.format == Format::Binary || f.appended_base64;
  e.header_apart = r.stored.header_apart;
  e.float32 = a.type == Scalar::Float32;
  e.blocks = r.stored.blocks;
  e.block_size = r.stored.block_size;
  e.last_block_size = r.stored.last_block_size;
  e.begin = r.stored.encoded_begin;
  e.end = r.stored.encoded_end;
  if (a.format == Format::Appended)
    for (const AppendedOffset& o : f.offsets)
      if (o.value > a.begin - f.appended) e.later.push_back(o);
  return std::make_shared<EncodedVtuPoints>(std::move(bytes), std::move(e), std::string(r.stored.values(f.bytes)));
}

std::string encoding_name(const Vtu& f, const DataArray* points) {
  if (!points) return f.layout.zlib ? "zlib" : "";
  std::string name = points->format == Format::Ascii    ? "ascii"
                     : points->format == Format::Binary ? "binary"
                     : f.appended_base64               ? "appended base64"
                                                       : "appended raw";
  if (f.layout.zlib && points->format != Format::Ascii) name += " zlib";
  return name;
}

std::uint64_t count_attribute(const Vtu& f, pugi::xml_node piece, const char* name, std::uint64_t max) {
  long long n;
  if (!parse_integer(piece.attribute(name).value(), n) || n < 0 || static_cast<unsigned long long>(n) > max)
    fail(f, node_offset(f, piece), std::string("the Piece's ") + name + " is not a count from 0 to " + std::to_string(max));
  return static_cast<std::uint64_t>(n);
}

}  // namespace

VolumeRead read_vtu(SharedBytes bytes, const std::string& path) {
  Vtu f(*bytes, path);
  split_appended(f);
  parse_xml(f);
  VolumeRead out;
  const pugi::xml_node root = read_root(f, out.source.version);
  if (f.appended != kNone) {
    const std::string_view encoding = root.child("AppendedData").attribute("encoding").value();
    if (encoding != "raw" && encoding != "base64")
      fail(f, f.appended, "AppendedData encoding '" + std::string(encoding) + "' is not raw or base64");
    f.appended_base64 = encoding == "base64";
    if (f.appended_base64)
      while (f.appended_end > f.appended && is_space(f.bytes[f.appended_end - 1])) --f.appended_end;
  }
  collect_offsets(f);
  const pugi::xml_node piece = find_piece(f, root);
  const std::uint64_t nodes = count_attribute(f, piece, "NumberOfPoints", UINT32_MAX);
  const std::uint64_t ncells = count_attribute(f, piece, "NumberOfCells", std::uint64_t{1} << 40);
  const pugi::xml_node points_node = piece.child("Points").child("DataArray");
  std::optional<DataArray> points;
  if (points_node) points = declare(f, points_node);
  else if (nodes > 0) fail(f, node_offset(f, piece), "the Piece has nodes but no Points DataArray");
  PointsRead r;
  if (points) r = read_points(f, *points, nodes);
  out.source.format = VolumeFormat::Vtu;
  out.source.encoding = encoding_name(f, points ? &*points : nullptr);
  out.source.cells = read_cells(f, piece, ncells, nodes);
  out.points = r.points;
  if (points) out.source.file = points_file(f, bytes, *points, r);
  else out.source.file = std::make_shared<TextPoints>(bytes, std::vector<std::uint64_t>{}, 3, Eigen::Matrix3Xd(3, 0));
  return out;
}

}  // namespace ffd
