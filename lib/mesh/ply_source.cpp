#include "mesh/ply_source.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstring>

#include "common/numbers.h"
#include "mesh/mesh.h"
#include "mesh/text_sink.h"
#include "mesh/vertex_colors.h"

namespace ffd {

std::size_t ply_type_size(PlyType type) {
  switch (type) {
    case PlyType::Int8: case PlyType::Uint8: return 1;
    case PlyType::Int16: case PlyType::Uint16: return 2;
    case PlyType::Int32: case PlyType::Uint32: case PlyType::Float32: return 4;
    case PlyType::Float64: return 8;
  }
  return 8;
}

bool ply_integer(PlyType type) { return type != PlyType::Float32 && type != PlyType::Float64; }

const char* ply_type_name(PlyType type) {
  static const char* const kNames[] = {"char", "uchar", "short", "ushort", "int", "uint", "float", "double"};
  return kNames[static_cast<int>(type)];
}

void ply_store(PlyType type, double x, unsigned char* out) {
  const auto put = [out](auto v) { std::memcpy(out, &v, sizeof v); };
  switch (type) {
    case PlyType::Int8: return put(static_cast<std::int8_t>(x));
    case PlyType::Uint8: return put(static_cast<std::uint8_t>(x));
    case PlyType::Int16: return put(static_cast<std::int16_t>(x));
    case PlyType::Uint16: return put(static_cast<std::uint16_t>(x));
    case PlyType::Int32: return put(static_cast<std::int32_t>(x));
    case PlyType::Uint32: return put(static_cast<std::uint32_t>(x));
    case PlyType::Float32: return put(static_cast<float>(x));
    case PlyType::Float64: return put(x);
  }
}

// The value of `type` at p (native byte order), as a double: exact for every PLY type.
double ply_load(PlyType type, const unsigned char* p) {
  const auto get = [p](auto v) {
    std::memcpy(&v, p, sizeof v);
    return static_cast<double>(v);
  };
  switch (type) {
    case PlyType::Int8: return get(std::int8_t{});
    case PlyType::Uint8: return get(std::uint8_t{});
    case PlyType::Int16: return get(std::int16_t{});
    case PlyType::Uint16: return get(std::uint16_t{});
    case PlyType::Int32: return get(std::int32_t{});
    case PlyType::Uint32: return get(std::uint32_t{});
    case PlyType::Float32: return get(float{});
    case PlyType::Float64: return get(double{});
  }
  return 0;
}

std::vector<std::string> PlySource::carried_only_here() const {
  std::vector<std::string> names;
  for (const PlyElementData& e : elements) {
    const bool known = &e == &elements[vertex_element] || e.name == "face" || e.name == "tristrips";
    if (!known) {
      names.push_back("element " + e.name);
      continue;
    }
    for (const PlyColumn& c : e.columns)
      if (c.role == PlyColumn::Role::Kept && !c.in_mesh) names.push_back(e.name + " " + c.name);
  }
  return names;
}

namespace {

// The type a column is written in: an integer coordinate or normal becomes a double.
PlyType written_type(const PlyColumn& c) {
  const bool computed = c.role == PlyColumn::Role::Position || c.role == PlyColumn::Role::Normal;
  return computed && ply_integer(c.type) ? PlyType::Float64 : c.type;
}

// The binary PLY format in the machine's byte order.
PlySource::Format native_format() {
  const std::uint16_t one = 1;
  unsigned char low;
  std::memcpy(&low, &one, 1);
  return low == 1 ? PlySource::Format::BinaryLittle : PlySource::Format::BinaryBig;
}

// Writes the values of one item after another in the output's encoding: ASCII text
// separated by spaces, one item a line; or binary in the output's byte order.
class PlyWriter {
public:
  PlyWriter(TextSink& out, PlySource::Format format, const std::string& line_end)
      : out_(out), format_(format), line_end_(line_end) {}

  /// A value read from the file, as its bytes of `type` (native order).
  void kept(PlyType type, const unsigned char* p) {
    if (format_ != PlySource::Format::Ascii) return bytes(p, ply_type_size(type));
    separate();
    char buf[kNumberChars];
    char* end = buf;
    if (ply_integer(type)) end = std::to_chars(buf, buf + sizeof buf, static_cast<long long>(ply_load(type, p))).ptr;
    else if (type == PlyType::Float32) end = std::to_chars(buf, buf + sizeof buf, static_cast<float>(ply_load(type, p))).ptr;
    else end = std::to_chars(buf, buf + sizeof buf, ply_load(type, p)).ptr;
    out_.put(std::string_view(buf, static_cast<std::size_t>(end - buf)));
  }
  /// A computed value, rounded to `type` as a cast does.
  void computed(PlyType type, double x) {
    if (format_ == PlySource::Format::Ascii && x == 0.0) x = 0.0;  // -0 as 0, as the text writers have it
    unsigned char b[8];
    ply_store(type, x, b);
    kept(type, b);
  }
  void end_item() {
    if (format_ == PlySource::Format::Ascii) out_.put(line_end_);
    first_ = true;
  }

private:
  void separate() {
    if (!first_) out_.put(' ');
    first_ = false;
  }
  void bytes(const unsigned char* p, std::size_t n) {
    unsigned char b[8];
    ply_copy(b, p, n, format_ != native_format());
    out_.put(std::string_view(reinterpret_cast<const char*>(b), n));
  }

  TextSink& out_;
  PlySource::Format format_;
  const std::string& line_end_;
  bool first_ = true;
};

const char* format_line(PlySource::Format format) {
  return format == PlySource::Format::Ascii ? "format ascii 1.0"
         : format == PlySource::Format::BinaryLittle ? "format binary_little_endian 1.0"
                                                     : "format binary_big_endian 1.0";
}

// Whether the vertex element has all of red, green and blue.
bool has_colors(const PlyElementData& vertex) {
  return std::count_if(vertex.columns.begin(), vertex.columns.end(),
                       [](const PlyColumn& c) { return c.role == PlyColumn::Role::Color; }) == 3;
}

// The header's lines as read, but for the format line, promoted coordinate types and,
// when `add_colors`, red green blue after the vertex element's last property.
void put_header(TextSink& out, const PlySource& source, PlySource::Format format, bool add_colors) {
  const PlyElementData& vertex = source.elements[source.vertex_element];
  std::size_t vertex_end = vertex.line;
  for (const PlyColumn& c : vertex.columns) vertex_end = std::max(vertex_end, c.line);
  std::vector<const PlyColumn*> promoted(source.header.size(), nullptr);
  for (const PlyColumn& c : vertex.columns)
    if (written_type(c) != c.type) promoted[c.line] = &c;
  for (std::size_t i = 0; i < source.header.size(); ++i) {
    if (i == source.format_line) out.put(format_line(format));
    else if (promoted[i]) out.put("property double " + promoted[i]->name);
    else out.put(source.header[i]);
    out.put(source.line_end);
    if (add_colors && i == vertex_end)
      for (const char* name : {"red", "green", "blue"}) {
        out.put(std::string("property uchar ") + name);
        out.put(source.line_end);
      }
  }
}

// Item i of a scalar column whose value the writer computes (a position, a normal, a
// painted colour) in the type it is written in: its bytes at b (native order), true; or
// false for a value as read.
bool computed_bytes(const PlyColumn& c, std::size_t i, const Mesh& mesh, const Eigen::Matrix3Xd* normals,
                    const std::vector<Eigen::Vector3f>* colors, unsigned char* b) {
  const auto v = static_cast<Eigen::Index>(i);
  switch (c.role) {
    case PlyColumn::Role::Position: ply_store(written_type(c), mesh.positions()(c.component, v), b); return true;
    case PlyColumn::Role::Normal:  // the file's normals carried through the warps, else the mesh's
      ply_store(written_type(c), normals ? (*normals)(c.component, v) : mesh.normals()(c.component, v), b);
      return true;
    case PlyColumn::Role::Color:
      if (!colors) return false;
      ply_store(c.type, ply_integer(c.type) ? color_byte((*colors)[i][c.component]) : (*colors)[i][c.component], b);
      return true;
    case PlyColumn::Role::Kept: return false;
  }
  return false;
}

// The items of a binary element whose columns are all scalars, a row at a time: each
// value in the output's byte order (`swap`: not the machine's), the painted colours
// after the last column when `add_colors`.
void put_scalar_rows(TextSink& out, const PlyElementData& element, bool swap, const Mesh& mesh,
                     const Eigen::Matrix3Xd* normals, const std::vector<Eigen::Vector3f>* colors, bool add_colors) {
  std::size_t row = add_colors ? 3 : 0;
  for (const PlyColumn& c : element.columns) row += ply_type_size(written_type(c));
  std::vector<unsigned char> buffer(row);
  for (std::size_t i = 0; i < element.count; ++i) {
    unsigned char* at = buffer.data();
    for (const PlyColumn& c : element.columns) {
      const std::size_t size = ply_type_size(written_type(c));
      unsigned char b[8];
      const bool computed = computed_bytes(c, i, mesh, normals, colors, b);
      ply_copy(at, computed ? b : c.values.data() + i * size, size, swap);
      at += size;
    }
    for (int k = 0; add_colors && k < 3; ++k) *at++ = static_cast<unsigned char>(color_byte((*colors)[i][k]));
    out.put(std::string_view(reinterpret_cast<const char*>(buffer.data()), row));
  }
}

// Item i of a column (and of its list's entries from `entry` on, which it advances).
void put_column(PlyWriter& w, const PlyColumn& c, std::size_t i, std::size_t& entry, const Mesh& mesh,
                const Eigen::Matrix3Xd* normals, const std::vector<Eigen::Vector3f>* colors) {
  unsigned char b[8];
  if (computed_bytes(c, i, mesh, normals, colors, b)) return w.computed(written_type(c), ply_load(written_type(c), b));
  const std::size_t size = ply_type_size(c.type);
  if (!c.list) return w.kept(c.type, c.values.data() + i * size);
  w.computed(c.count_type, c.lengths[i]);
  for (std::uint32_t k = 0; k < c.lengths[i]; ++k, ++entry) w.kept(c.type, c.values.data() + entry * size);
}

}  // namespace

void write_ply_source(std::ostream& os, const Mesh& mesh, const Eigen::Matrix3Xd* normals,
                      const std::vector<Eigen::Vector3f>* colors, bool binary) {
  const PlySource& source = *mesh.ply_source();
  const PlySource::Format format = !binary ? PlySource::Format::Ascii
                                   : source.format == PlySource::Format::Ascii ? PlySource::Format::BinaryLittle
                                                                               : source.format;
  TextSink out(os);
  const bool add_colors = colors && !has_colors(source.elements[source.vertex_element]);
  put_header(out, source, format, add_colors);
  PlyWriter w(out, format, source.line_end);
  for (std::size_t e = 0; e < source.elements.size(); ++e) {
    const PlyElementData& element = source.elements[e];
    const bool vertex = e == source.vertex_element;
    if (element.columns.empty() && !(vertex && add_colors)) continue;  // items of no bytes
    const bool scalars = std::none_of(element.columns.begin(), element.columns.end(), [](const PlyColumn& c) { return c.list; });
    if (format != PlySource::Format::Ascii && scalars) {
      put_scalar_rows(out, element, format != native_format(), mesh, normals, colors, vertex && add_colors);
      continue;
    }
    std::vector<std::size_t> entries(element.columns.size(), 0);
    for (std::size_t i = 0; i < element.count; ++i) {
      for (std::size_t k = 0; k < element.columns.size(); ++k)
        put_column(w, element.columns[k], i, entries[k], mesh, normals, colors);
      if (vertex && add_colors)
        for (int k = 0; k < 3; ++k) w.computed(PlyType::Uint8, color_byte((*colors)[i][k]));
      w.end_item();
    }
  }
  out.flush();
}

}  // namespace ffd
