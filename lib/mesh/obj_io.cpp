#include "mesh/obj_io.h"


#include "common/errors.h"
#include "common/numbers.h"
#include <algorithm>
#include "mesh/text_lines.h"

namespace ffd {
namespace {

// Resolves an OBJ index (1-based, or negative = relative to the end) against `count`
// elements read so far; throws with the line number when it points nowhere.
std::int64_t resolve_index(std::string_view token, std::size_t count, const std::string& file,
                           std::size_t line, const char* what) {
  long long raw;
  if (!parse_integer(token, raw) || raw == 0)
    throw InputError(place(file, line) + ": " + what + " index '" + std::string(token) +
                     "' is not a non-zero integer");
  const long long resolved = raw > 0 ? raw - 1 : static_cast<long long>(count) + raw;
  if (resolved < 0 || resolved >= static_cast<long long>(count))
    throw InputError(place(file, line) + ": " + what + " index " + std::string(token) +
                     " is out of range (" + std::to_string(count) + " defined so far)");
  return resolved;
}

std::string rest_of_line(std::string_view line, std::string_view keyword) {
  std::size_t hash = line.find('#');
  if (hash != std::string_view::npos) line = line.substr(0, hash);
  std::size_t start = line.find(keyword) + keyword.size();
  while (start < line.size() && (line[start] == ' ' || line[start] == '\t')) ++start;
  std::size_t end = line.size();
  while (end > start && (line[end - 1] == ' ' || line[end - 1] == '\t')) --end;
  return std::string(line.substr(start, end - start));
}

// Appends `v x y z`, `v x y z w` (w = 1 only) or `v x y z r g b` on line n to `soup`.
// Colours start with the first coloured vertex; earlier vertices get the default grey.
void read_vertex(const std::vector<std::string_view>& tokens, const std::string& file, std::size_t n,
                 PolygonSoup& soup, bool& any_color) {
  if (tokens.size() != 4 && tokens.size() != 5 && tokens.size() != 7)
    throw InputError(place(file, n) + ": expected 'v x y z' (or with w, or with r g b), found " +
                     std::to_string(tokens.size() - 1) + " values");
  Eigen::Vector3d p;
  for (int i = 0; i < 3; ++i) p[i] = number_or_throw(tokens[1 + i], file, n, "coordinate");
  if (tokens.size() == 5 && number_or_throw(tokens[4], file, n, "weight") != 1.0)
    throw InputError(place(file, n) + ": rational vertices (w != 1) are not supported");
  Eigen::Vector3f c(0.8f, 0.8f, 0.8f);
  if (tokens.size() == 7) {
    for (int i = 0; i < 3; ++i) c[i] = static_cast<float>(number_or_throw(tokens[4 + i], file, n, "colour"));
    if (!any_color) {
      soup.colors.assign(soup.positions.size(), Eigen::Vector3f(0.8f, 0.8f, 0.8f));
      any_color = true;
    }
  }
  soup.positions.push_back(p);
    if (any_color) soup.colors.push_back(c);
}

// Appends `vt u [v [w]]` on line n to `soup` (w is checked, then dropped).
void read_texture_coordinate(const std::vector<std::string_view>& tokens, const std::string& file, std::size_t n,
                             PolygonSoup& soup) {
  if (tokens.size() < 2 || tokens.size() > 4)
    throw InputError(place(file, n) + ": expected 'vt u [v [w]]'");
  Eigen::Vector2d t(number_or_throw(tokens[1], file, n, "texture coordinate"), 0.0);
  if (tokens.size() >= 3) t[1] = number_or_throw(tokens[2], file, n, "texture coordinate");
  if (tokens.size() == 4) number_or_throw(tokens[3], file, n, "texture coordinate");
  soup.uvs.push_back(t);
}

// Appends `vn x y z` on line n to `soup`.
void read_normal(const std::vector<std::string_view>& tokens, const std::string& file, std::size_t n,
                 PolygonSoup& soup) {
  if (tokens.size() != 4) throw InputError(place(file, n) + ": expected 'vn x y z'");
  Eigen::Vector3d v;
  for (int i = 0; i < 3; ++i) v[i] = number_or_throw(tokens[1 + i], file, n, "normal component");
  soup.normals.push_back(v);
}

// Splits a face corner `v`, `v/t`, `v//n` or `v/t/n` into its index tokens (empty if absent).
void split_corner(std::string_view corner, std::string_view& vtok, std::string_view& ttok, std::string_view& ntok) {
  std::size_t s1 = corner.find('/');
  vtok = corner.substr(0, s1);
  if (s1 != std::string_view::npos) {
    std::size_t s2 = corner.find('/', s1 + 1);
    ttok = corner.substr(s1 + 1, s2 == std::string_view::npos ? std::string_view::npos : s2 - s1 - 1);
    if (s2 != std::string_view::npos) ntok = corner.substr(s2 + 1);
  }
}

// The element `f c1 c2 c3 ...`, `l c1 c2 ...` or `p c1 ...` on line n, its corners
// resolved against what `soup` holds so far, appended to its elements.
void read_element(const std::vector<std::string_view>& tokens, ElementKind kind, std::int32_t group,
                  const std::string& file, std::size_t n, PolygonSoup& soup) {
  const std::size_t least = kind == ElementKind::Polygon ? 3 : kind == ElementKind::Line ? 2 : 1;
  if (tokens.size() < least + 1)
    throw InputError(place(file, n) + ": " +
                     (kind == ElementKind::Polygon ? "a face" : kind == ElementKind::Line ? "a line" : "a point element") +
                     " needs at least " + std::to_string(least) + " vertices, found " + std::to_string(tokens.size() - 1));
  for (std::size_t i = 1; i < tokens.size(); ++i) {
    std::string_view vtok, ttok, ntok;
    split_corner(tokens[i], vtok, ttok, ntok);
    const auto v = static_cast<std::uint32_t>(resolve_index(vtok, soup.positions.size(), file, n, "vertex"));
    std::int32_t t = -1, nn = -1;
    if (!ttok.empty()) t = static_cast<std::int32_t>(resolve_index(ttok, soup.uvs.size(), file, n, "texture"));
    if (!ntok.empty()) nn = static_cast<std::int32_t>(resolve_index(ntok, soup.normals.size(), file, n, "normal"));
    soup.elements.add_corner(v, t, nn);
  }
  soup.elements.close(kind, group, static_cast<std::uint32_t>(std::min<std::size_t>(n, 0xffffffffu)));
}

// Applies an `o`, `g`, `usemtl` or `s` statement to `state`; sets `changed` when it
// differs from what was in force.
void set_state(std::string_view line, std::string_view key, ObjState& state, bool& changed) {
  std::string value = rest_of_line(line, key);
  std::string* slot = key == "o" ? &state.object
                      : key == "g" ? &state.group
                      : key == "usemtl" ? &state.material
                                        : &state.smoothing;
  if (*slot != value) {
    *slot = value;
    changed = true;
  }
}

}  // namespace

PolygonSoup read_obj(std::string_view text, const std::string& file) {
  PolygonSoup soup;
  LineScanner lines(text);
  std::string_view line;
  std::vector<std::string_view> tokens;
  ObjState state;
  bool state_changed = false;
  bool any_color = false;

  while (lines.next(line)) {
    const std::size_t n = lines.number();
    split_tokens(line, tokens);
    if (tokens.empty()) continue;
    const std::string_view key = tokens[0];
    if (key == "v") {
      read_vertex(tokens, file, n, soup, any_color);
    } else if (key == "vt") {
      read_texture_coordinate(tokens, file, n, soup);
    } else if (key == "vn") {
      read_normal(tokens, file, n, soup);
    } else if (key == "f" || key == "l" || key == "p") {
      if (state_changed) {
        soup.groups.push_back(state);
        state_changed = false;
      }
      const ElementKind kind = key == "f" ? ElementKind::Polygon : key == "l" ? ElementKind::Line : ElementKind::Point;
      read_element(tokens, kind, static_cast<std::int32_t>(soup.groups.size()) - 1, file, n, soup);
    } else if (key == "o" || key == "g" || key == "usemtl" || key == "s") {
      set_state(line, key, state, state_changed);
    } else if (key == "mtllib") {
      soup.header.push_back("mtllib " + rest_of_line(line, key));
    } else {
      throw InputError(place(file, n) + ": unsupported OBJ statement '" + std::string(key) + "'");
    }
  }
  return soup;
}

namespace {

void append_state_change(std::string& out, const ObjState& from, const ObjState& to) {
  if (to.object != from.object) out += "o " + to.object + "\n";
  if (to.group != from.group) out += "g " + to.group + "\n";
  if (to.material != from.material) out += "usemtl " + to.material + "\n";
  if (to.smoothing != from.smoothing) out += "s " + to.smoothing + "\n";
}

}  // namespace

namespace {

// Appends element e's statement ("f", "l" or "p" and its corners) to `out`.
void append_element(std::string& out, const MeshElements& el, std::size_t e, const std::vector<std::int64_t>& corner_vn) {
  out += el.kinds[e] == ElementKind::Polygon ? 'f' : el.kinds[e] == ElementKind::Line ? 'l' : 'p';
  for (std::uint32_t c = el.begin(e); c < el.end(e); ++c) {
    out += ' ';
    out += std::to_string(el.corners[c] + 1);
    const std::int32_t t = el.uv(c);
    const std::int64_t nn = corner_vn.empty() ? -1 : corner_vn[c];
    if (t >= 0 || nn >= 0) {
      out += '/';
      if (t >= 0) out += std::to_string(t + 1);
      if (nn >= 0) {
        out += '/';
        out += std::to_string(nn + 1);
      }
    }
  }
  out += '\n';
}

// Appends "tag a b c\n" (or with two values) to `out`.
template <class Vec>
void append_vector_line(std::string& out, const char* tag, const Vec& v) {
  out += tag;
  for (Eigen::Index k = 0; k < v.size(); ++k) {
    out += ' ';
    append_number(out, v[k]);
  }
  out += '\n';
}

// Writes `out` to `os` once it holds more than 4 MB, so memory stays bounded.
void flush_if_large(std::ostream& os, std::string& out) {
  if (out.size() < (1u << 22)) return;
  os.write(out.data(), static_cast<std::streamsize>(out.size()));
  out.clear();
}

}  // namespace

void write_obj(std::ostream& os, const Mesh& mesh, const NormalTransform& transform_normal,
               VertexColors colors) {
  std::string out;
  out.reserve(1u << 23);
  for (const std::string& line : mesh.header()) out += line + "\n";
  const ConstVec3Array p = mesh.positions();
  for (Eigen::Index i = 0; i < p.cols(); ++i) {
    out += 'v';
    for (int k = 0; k < 3; ++k) {
      out += ' ';
      append_number(out, p(k, i));
    }
    if (colors)
      for (int k = 0; k < 3; ++k) {
        out += ' ';
        append_number(out, (*colors)[static_cast<std::size_t>(i)][k]);
      }
    out += '\n';
    flush_if_large(os, out);
  }
  for (const Eigen::Vector2d& t : mesh.uvs()) append_vector_line(out, "vt", t);
  // Normals: each corner's file normal carried to its vertex's deformed frame.
  const CornerNormals normals = transformed_file_normals(mesh, transform_normal);
  for (const Eigen::Vector3d& n : normals.table) append_vector_line(out, "vn", n);

  const MeshElements& el = mesh.elements();
  ObjState current;
  for (std::size_t e = 0; e < el.size(); ++e) {
    const std::int32_t g = el.group(e);
    const ObjState& next = g >= 0 ? mesh.groups()[g] : ObjState{};
    append_state_change(out, current, next);
    current = next;
    append_element(out, el, e, normals.corner);
    flush_if_large(os, out);
  }
  os.write(out.data(), static_cast<std::streamsize>(out.size()));
}

}  // namespace ffd
