#include "mesh/obj_io.h"

#include <omp.h>

#include <algorithm>
#include <charconv>
#include <cstring>
#include <limits>
#include <memory>
#include <optional>

#include "common/errors.h"
#include "common/numbers.h"
#include "common/zeroed_array.h"
#include "mesh/obj_chunks.h"
#include "mesh/obj_source.h"
#include "mesh/soup_chunks.h"
#include "mesh/text_lines.h"
#include "mesh/text_sink.h"

namespace ffd {
namespace {

// Resolves an OBJ index (1-based, or negative = relative to the end) against `count`
// elements read so far; throws with the line number when it points nowhere.
std::int64_t resolve_index(std::string_view token, std::size_t count, const std::string& file,
                           std::size_t line, const char* what) {
  long long raw;
  if (!parse_integer(token, raw) || raw == 0)
    throw InputError(At{place(file, line)}, std::string(what) + " index '" + std::string(token) +
                     "' is not a non-zero integer");
  const long long resolved = raw > 0 ? raw - 1 : static_cast<long long>(count) + raw;
  if (resolved < 0 || resolved >= static_cast<long long>(count))
    throw InputError(At{place(file, line)}, std::string(what) + " index " + std::string(token) +
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

// Appends `v x y z`, `v x y z w` or `v x y z r g b` on line n to `soup`, and w to `w`
// (NaN for the vertices before the first w, and for any without one after it).
// Colours start with the first coloured vertex; earlier vertices get the default grey.
void read_vertex(const std::vector<std::string_view>& tokens, const std::string& file, std::size_t n,
                 PolygonSoup& soup, bool& any_color, std::vector<double>& w) {
  if (tokens.size() != 4 && tokens.size() != 5 && tokens.size() != 7)
    throw InputError(At{place(file, n)}, "expected 'v x y z' (or with w, or with r g b), found " +
                     std::to_string(tokens.size() - 1) + " values");
  Eigen::Vector3d p;
  for (int i = 0; i < 3; ++i) p[i] = number_or_throw(tokens[1 + i], file, n, "coordinate");
  if (tokens.size() == 5) {
    if (w.empty()) w.assign(soup.positions.size(), std::numeric_limits<double>::quiet_NaN());
    w.push_back(number_or_throw(tokens[4], file, n, "weight"));
  } else if (!w.empty()) {
    w.push_back(std::numeric_limits<double>::quiet_NaN());
  }
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
    throw InputError(At{place(file, n)}, "expected 'vt u [v [w]]'");
  Eigen::Vector2d t(number_or_throw(tokens[1], file, n, "texture coordinate"), 0.0);
  if (tokens.size() >= 3) t[1] = number_or_throw(tokens[2], file, n, "texture coordinate");
  if (tokens.size() == 4) number_or_throw(tokens[3], file, n, "texture coordinate");
  soup.uvs.push_back(t);
}

// Appends `vn x y z` on line n to `soup`.
void read_normal(const std::vector<std::string_view>& tokens, const std::string& file, std::size_t n,
                 PolygonSoup& soup) {
  if (tokens.size() != 4) throw InputError(At{place(file, n)}, "expected 'vn x y z'");
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
    throw InputError(At{place(file, n)}, std::string(kind == ElementKind::Polygon ? "a face" : kind == ElementKind::Line ? "a line" : "a point element") +
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
  soup.elements.close(kind, group, n);
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

// What the reader carries from line to line.
struct ObjReadState {
  ObjState obj;          // the o/g/usemtl/s state in force
  bool changed = false;  // since the last element
  bool any_color = false;
  ObjSource extra;       // what is kept without being interpreted
};

// The fast path for the two lines that make up nearly every OBJ, `v x y z` and
// `f c1 c2 c3 ...` (corners `v`, `v/t`, `v//n`, `v/t/n`): they are parsed in place,
// without splitting into tokens. A fast reader returns false, having changed nothing,
// at anything it does not take in full (a comment, a '+' sign, colours, a bad index);
// the general path then reads that line and gives its error, so both paths accept the
// same text and build the same soup (tests and the obj fuzz target check this).

// A non-zero index at p resolved against `count` (as resolve_index does), ending at a
// blank, '/', or the line's end when `slash` is set (else at a blank or the end).
bool fast_index(const char*& p, const char* end, const char* readable, std::size_t count, bool slash,
                std::int64_t& index) {
  long long raw = 0;
  const auto [next, ec] = decimal(p, end, raw, readable);
  if (ec != std::errc() || next == p || raw == 0) return false;
  if (next < end && !blank(*next) && !(slash && *next == '/')) return false;
  const long long resolved = raw > 0 ? raw - 1 : static_cast<long long>(count) + raw;
  if (resolved < 0 || resolved >= static_cast<long long>(count)) return false;
  p = next;
  index = resolved;
  return true;
}

bool read_vertex_fast(std::string_view line, PolygonSoup& soup, bool any_color, std::vector<double>& w) {
  Eigen::Vector3d v;
  if (!fast_numbers_to_end(line.data() + 1, line.data() + line.size(), v.data(), 3)) return false;
  soup.positions.push_back(v);
  if (any_color) soup.colors.push_back(Eigen::Vector3f(0.8f, 0.8f, 0.8f));
  if (!w.empty()) w.push_back(std::numeric_limits<double>::quiet_NaN());
  return true;
}

// One corner `v`, `v/t`, `v//n` or `v/t/n` at p, into `corner` (t, n: -1 when absent).
bool fast_corner(const char*& p, const char* end, const char* readable, const PolygonSoup& soup,
                 std::int64_t corner[3]) {
  corner[1] = corner[2] = -1;
  if (!fast_index(p, end, readable, soup.positions.size(), true, corner[0])) return false;
  if (p == end || *p != '/') return true;
  ++p;
  if (p < end && *p != '/' && !fast_index(p, end, readable, soup.uvs.size(), true, corner[1])) return false;
  if (p == end || *p != '/') return p == end || blank(*p);
  ++p;
  return fast_index(p, end, readable, soup.normals.size(), false, corner[2]);
}

// A face of up to 8 corners that are vertex indices alone (`f 1 2 3`, nearly every
// face of a mesh without UVs or normals), read straight into the soup; false, having
// changed nothing, at anything else (read_face_fast then reads the line whole).
bool read_plain_face(const char* p, const char* end, const char* readable, std::int32_t group, std::size_t n,
                     PolygonSoup& soup) {
  std::int64_t v[8];
  int count = 0;
  for (p = skip_blanks(p, end); p < end; p = skip_blanks(p, end)) {
    if (count == 8 || !fast_index(p, end, readable, soup.positions.size(), true, v[count]) || (p < end && *p == '/'))
      return false;
    ++count;
  }
  if (count < 3) return false;
  for (int c = 0; c < count; ++c) soup.elements.add_corner(static_cast<std::uint32_t>(v[c]));
  soup.elements.close(ElementKind::Polygon, group, n);
  return true;
}

bool read_face_fast(std::string_view line, const char* readable, std::int32_t group, std::size_t n, PolygonSoup& soup,
                    std::vector<std::int64_t>& corners) {
  const char* p = line.data() + 1;
  const char* end = line.data() + line.size();
  // A line with a '/' has UV or normal indices: not a plain face (which would parse its
  // first index before finding out).
  const bool plain = std::memchr(p, '/', static_cast<std::size_t>(end - p)) == nullptr;
  if (plain && read_plain_face(p, end, readable, group, n, soup)) return true;
  corners.clear();
  for (p = skip_blanks(p, end); p < end; p = skip_blanks(p, end)) {
    std::int64_t c[3];
    if (!fast_corner(p, end, readable, soup, c)) return false;
    corners.insert(corners.end(), c, c + 3);
  }
  if (corners.size() < 9) return false;
  for (std::size_t i = 0; i < corners.size(); i += 3)
    soup.elements.add_corner(static_cast<std::uint32_t>(corners[i]), static_cast<std::int32_t>(corners[i + 1]),
                             static_cast<std::int32_t>(corners[i + 2]));
  soup.elements.close(ElementKind::Polygon, group, n);
  return true;
}

// Reserves the soup's arrays once for the `v` and `f` lines the text can hold, rather than
// growing them. A valid `v` or `f` line takes at least 8 bytes with its newline ("v 0 0 0";
// the last line 7), so (size + 1) / 8 lines of each bound them. Where unused reserved
// memory costs nothing (reserving_is_free: no address-space limit, no strict commit) that
// bound is reserved as is, with no pass over the text: on a 1M-vertex file read_ms
// 232 -> 211. Elsewhere the lines are counted in one pass (17 ms on that file) and exactly
// those reserved, so that a limit refuses no file it would take with exact arrays; junk
// input ("v \nv \n...") then reserves no more than the same bytes of valid lines need.
void reserve_for(std::string_view text, PolygonSoup& soup) {
  const std::size_t most = (text.size() + 1) / 8;
  std::size_t vertices = most, faces = most;
  if (!reserving_is_free(most * kSoupLineBytes)) {
    const auto [v, f] = count_keyed_lines(text, 'v', 'f');
    vertices = std::min(v, most), faces = std::min(f, most - vertices);
  }
  reserve_for_lines(soup, vertices, faces);
}

// Whether `key` can name an OBJ statement: a letter or '_', then letters, digits, '_'.
// Anything else (binary junk, UTF-16 text) is refused rather than carried.
bool statement_keyword(std::string_view key) {
  const auto word = [](char c, bool first) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_' || (!first && c >= '0' && c <= '9');
  };
  if (key.empty() || !word(key[0], true)) return false;
  return std::all_of(key.begin() + 1, key.end(), [&](char c) { return word(c, false); });
}

// Keeps a statement ffdtool does not interpret (line n), to be written back in place.
void keep_statement(std::string_view line, std::string_view key, const std::string& file, std::size_t n,
                    const PolygonSoup& soup, ObjSource& extra) {
  if (!statement_keyword(key))
    throw InputError(At{place(file, n)}, "unsupported OBJ statement '" + std::string(key) + "'");
  extra.statements.push_back({soup.elements.size(), soup.positions.empty(), std::string(line)});
  const auto it = std::find_if(extra.keywords.begin(), extra.keywords.end(),
                               [&](const auto& k) { return k.first == key; });
  if (it == extra.keywords.end()) extra.keywords.emplace_back(std::string(key), 1);
  else ++it->second;
}

// A line ending in `\` (outside a comment) is continued on the next: the lines are joined
// into `joined`, each `\` becoming a space, and `line` views it. False for other lines.
bool join_continued(LineScanner& lines, std::string_view& line, std::string& joined) {
  const auto continues = [](std::string_view l) {
    return !l.empty() && l.back() == '\\' && l.find('#') == std::string_view::npos;
  };
  if (!continues(line)) return false;
  joined.assign(line.substr(0, line.size() - 1));
  std::string_view next;
  while (lines.next(next)) {
    joined += ' ';
    if (!continues(next)) {
      joined += next;
      break;
    }
    joined += next.substr(0, next.size() - 1);
  }
  line = joined;
  return true;
}

// One statement of the general path: every line the fast path did not take.
void read_statement(std::string_view line, const std::vector<std::string_view>& tokens, const std::string& file,
                    std::size_t n, PolygonSoup& soup, ObjReadState& state) {
  const std::string_view key = tokens[0];
  if (key == "v") {
    read_vertex(tokens, file, n, soup, state.any_color, state.extra.w);
  } else if (key == "vt") {
    read_texture_coordinate(tokens, file, n, soup);
  } else if (key == "vn") {
    read_normal(tokens, file, n, soup);
  } else if (key == "f" || key == "l" || key == "p") {
    if (state.changed) {
      soup.groups.push_back(state.obj);
      state.changed = false;
    }
    const ElementKind kind = key == "f" ? ElementKind::Polygon : key == "l" ? ElementKind::Line : ElementKind::Point;
    read_element(tokens, kind, static_cast<std::int32_t>(soup.groups.size()) - 1, file, n, soup);
  } else if (key == "o" || key == "g" || key == "usemtl" || key == "s") {
    set_state(line, key, state.obj, state.changed);
  } else if (key == "mtllib") {
    soup.header.push_back("mtllib " + rest_of_line(line, key));
  } else {
    keep_statement(line, key, file, n, soup, state.extra);
  }
}

// Whether read_obj tries the parallel path (obj_chunks.h): its chunks reserve room for
// twice the lines reserve_for does.
bool read_in_chunks(std::string_view text) {
  return worth_reading_in_chunks(text.size(), 2 * ((text.size() + 1) / 8) * kSoupLineBytes);
}

PolygonSoup read_obj_lines(std::string_view text, const std::string& file, bool fast,
                           const std::function<void()>& release_text = {}) {
  if (fast && read_in_chunks(text))
    if (std::optional<PolygonSoup> soup = read_plain_obj_in_chunks(text, omp_get_max_threads(), release_text))
      return std::move(*soup);
  PolygonSoup soup;
  reserve_for(text, soup);
  LineScanner lines(text);
  const char* const readable = text.data() + text.size();  // the fast paths may look past a line's end
  std::string_view line;
  std::string joined;
  std::vector<std::string_view> tokens;
  std::vector<std::int64_t> corners;
  ObjReadState state;
  while (lines.next(line)) {
    const std::size_t n = lines.number();
    const bool was_joined = join_continued(lines, line, joined);
    if (fast && !was_joined && line.size() > 2 && blank(line[1])) {
      if (line[0] == 'v' && read_vertex_fast(line, soup, state.any_color, state.extra.w)) continue;
      const auto group = static_cast<std::int32_t>(soup.groups.size()) - 1;
      if (line[0] == 'f' && !state.changed && read_face_fast(line, readable, group, n, soup, corners)) continue;
    }
    split_tokens(line, tokens);
    if (!tokens.empty()) read_statement(line, tokens, file, n, soup, state);
  }
  if (!state.extra.empty()) soup.obj = std::make_shared<const ObjSource>(std::move(state.extra));
  if (release_text) release_text();  // the soup and the kept statements are copies
  return soup;
}

}  // namespace

PolygonSoup read_obj(std::string_view text, const std::string& file) { return read_obj_lines(text, file, true); }

PolygonSoup read_obj(std::string_view text, const std::string& file, const std::function<void()>& release_text) {
  return read_obj_lines(text, file, true, release_text);
}

PolygonSoup read_obj_general(std::string_view text, const std::string& file) {
  return read_obj_lines(text, file, false);
}

namespace {

void put_state_change(TextSink& out, const ObjState& from, const ObjState& to) {
  const auto statement = [&out](const char* key, const std::string& value) {
    out.put(key);
    out.put(value);
    out.put('\n');
  };
  if (to.object != from.object) statement("o ", to.object);
  if (to.group != from.group) statement("g ", to.group);
  if (to.material != from.material) statement("usemtl ", to.material);
  if (to.smoothing != from.smoothing) statement("s ", to.smoothing);
}

// The statement an element of `kind` is written as.
char element_letter(ElementKind kind) {
  return kind == ElementKind::Polygon ? 'f' : kind == ElementKind::Line ? 'l' : 'p';
}

// Writes element e's statement ("f", "l" or "p" and its corners).
void put_element(TextSink& out, const MeshElements& el, std::size_t e, const std::vector<std::int64_t>& corner_vn) {
  out.put(element_letter(el.kinds[e]));
  for (std::uint32_t c = el.begin(e); c < el.end(e); ++c) {
    out.put(' ');
    out.integer(el.corners[c] + std::uint64_t{1});
    const std::int32_t t = el.uv(c);
    const std::int64_t nn = corner_vn.empty() ? -1 : corner_vn[c];
    if (t >= 0 || nn >= 0) {
      out.put('/');
      if (t >= 0) out.integer(t + std::int64_t{1});
      if (nn >= 0) {
        out.put('/');
        out.integer(nn + 1);
      }
    }
  }
  out.put('\n');
}

// put_element for an element of at most 16 corners with no UV or normal: the line's room
// claimed once (20 digits an index at most), then its indices written straight into it.
void put_plain_element(TextSink& out, const MeshElements& el, std::size_t e) {
  char* p = out.claim(2 + 21 * std::size_t{16});
  *p++ = element_letter(el.kinds[e]);
  for (std::uint32_t c = el.begin(e); c < el.end(e); ++c) {
    *p++ = ' ';
    p = std::to_chars(p, p + 20, el.corners[c] + std::uint64_t{1}).ptr;
  }
  *p++ = '\n';
  out.commit(p);
}

// Writes "tag a b c\n" (or with two values).
template <class Vec>
void put_vector_line(TextSink& out, const char* tag, const Vec& v) {
  out.put(tag);
  for (Eigen::Index k = 0; k < v.size(); ++k) {
    out.put(' ');
    out.number(v[k]);
  }
  out.put('\n');
}

// Writes the kept statements from `next` on that come before element `e` (all that are
// left when e is past the last element); advances `next`.
void put_statements(TextSink& out, const ObjSource* extra, std::size_t e, std::size_t& next) {
  if (!extra) return;
  for (; next < extra->statements.size() && extra->statements[next].before_element <= e; ++next) {
    out.put(extra->statements[next].text);
    out.put('\n');
  }
}

// The v lines: positions, then the colour when given, else the file's w where it had one.
void put_vertices(TextSink& out, const Mesh& mesh, VertexColors colors) {
  const ConstVec3Array p = mesh.positions();
  const ObjSource* extra = mesh.obj_source();
  const std::vector<double>* w = extra && !extra->w.empty() && !colors ? &extra->w : nullptr;
  if (!colors && !w) {  // "v x y z": the line's room claimed once
    put_ordered(out, 0, static_cast<std::size_t>(p.cols()), [&](TextSink& line, std::size_t i) {
      char* q = line.claim(2 + 3 * (1 + kNumberChars));
      *q++ = 'v';
      for (int k = 0; k < 3; ++k) {
        *q++ = ' ';
        q = format_number_to(q, p(k, static_cast<Eigen::Index>(i)));
      }
      *q++ = '\n';
      line.commit(q);
    });
    return;
  }
  put_ordered(out, 0, static_cast<std::size_t>(p.cols()), [&](TextSink& line, std::size_t i) {
    line.put('v');
    for (int k = 0; k < 3; ++k) {
      line.put(' ');
      line.number(p(k, static_cast<Eigen::Index>(i)));
    }
    if (colors)
      for (int k = 0; k < 3; ++k) {
        line.put(' ');
        line.number((*colors)[i][k]);
      }
    if (w && !std::isnan((*w)[i])) {
      line.put(' ');
      line.number((*w)[i]);
    }
    line.put('\n');
  });
}

// Whether a kept statement sits between two elements (not before the vertices, nor after
// the last element): then the elements are written in one pass that keeps them in place.
bool statements_between_elements(const ObjSource* extra, std::size_t elements) {
  if (!extra) return false;
  for (const ObjSource::Statement& s : extra->statements)
    if (!s.before_vertices && s.before_element < elements) return true;
  return false;
}

// The f, l and p lines, with the o/g/usemtl/s changes between them and the kept statements.
void put_elements(TextSink& out, const Mesh& mesh, const std::vector<std::int64_t>& corner_vn, std::size_t& next) {
  const MeshElements& el = mesh.elements();
  const ObjSource* extra = mesh.obj_source();
  static const ObjState none;
  const auto state = [&](std::int32_t g) -> const ObjState& { return g >= 0 ? mesh.groups()[g] : none; };
  // Element e's lines: the state change from element e - 1's group (none before the first).
  const bool plain = el.corner_uvs.empty() && corner_vn.empty();  // no corner has more than its vertex
  const auto element = [&](TextSink& line, std::size_t e) {
    const std::int32_t g = el.group(e), before = e > 0 ? el.group(e - 1) : -1;
    if (g != before) put_state_change(line, state(before), state(g));
    if (plain && el.degree(e) <= 16)
      put_plain_element(line, el, e);
    else
      put_element(line, el, e, corner_vn);
  };
  if (statements_between_elements(extra, el.size())) {
    for (std::size_t e = 0; e < el.size(); ++e) {
      put_statements(out, extra, e, next);
      element(out, e);
    }
  } else {
    put_ordered(out, 0, el.size(), element);
  }
  put_statements(out, extra, el.size(), next);
}

}  // namespace

void write_obj(std::ostream& os, const Mesh& mesh, const NormalTransform& transform_normal,
               VertexColors colors) {
  TextSink out(os);
  for (const std::string& line : mesh.header()) {
    out.put(line);
    out.put('\n');
  }
  const ObjSource* extra = mesh.obj_source();
  std::size_t next = 0;  // the first kept statement not yet written
  if (extra)
    for (; next < extra->statements.size() && extra->statements[next].before_vertices; ++next) {
      out.put(extra->statements[next].text);
      out.put('\n');
    }
  put_vertices(out, mesh, colors);
  for (const Eigen::Vector2d& t : mesh.uvs()) put_vector_line(out, "vt", t);
  // Normals: each corner's file normal carried to its vertex's deformed frame.
  const CornerNormals normals = transformed_file_normals(mesh, transform_normal);
  for (const Eigen::Vector3d& n : normals.table) put_vector_line(out, "vn", n);

  put_elements(out, mesh, normals.corner, next);
  out.flush();
}

}  // namespace ffd
