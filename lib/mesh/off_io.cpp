#include "mesh/off_io.h"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <optional>

#include "common/errors.h"
#include "common/numbers.h"
#include "common/zeroed_array.h"
#include "mesh/off_chunks.h"
#include "mesh/soup_chunks.h"
#include "mesh/text_lines.h"
#include "mesh/text_sink.h"

namespace ffd {
namespace {

struct OffHeader {
  bool st = false, color = false, normal = false;
};

bool parse_keyword(std::string_view word, OffHeader& h) {
  if (word.size() < 3 || word.substr(word.size() - 3) != "OFF") return false;
  std::string_view prefix = word.substr(0, word.size() - 3);
  if (prefix.substr(0, 2) == "ST") {
    h.st = true;
    prefix.remove_prefix(2);
  }
  if (!prefix.empty() && prefix[0] == 'C') {
    h.color = true;
    prefix.remove_prefix(1);
  }
  if (!prefix.empty() && prefix[0] == 'N') {
    h.normal = true;
    prefix.remove_prefix(1);
  }
  return prefix.empty();
}

// Reads a colour given as 3 or 4 components, either all integers 0..255 or floats 0..1.
Eigen::Vector3f parse_color(const std::vector<std::string_view>& t, std::size_t first,
                            std::size_t count, const std::string& file, std::size_t line) {
  Eigen::Vector3f c;
  bool integers = true;
  for (std::size_t i = 0; i < count; ++i)
    if (t[first + i].find_first_of(".eE") != std::string_view::npos) integers = false;
  for (int i = 0; i < 3; ++i) {
    double v = number_or_throw(t[first + i], file, line, "colour");
    c[i] = static_cast<float>(integers ? v / 255.0 : v);
  }
  return c;
}

// Reads the header keyword (a file may omit it) up to the counts, on its line or the
// next; returns the count tokens (views into the text), empty when the file ends first.
std::vector<std::string_view> read_header(LineScanner& lines, const std::string& file, OffHeader& header) {
  std::string_view line;
  std::vector<std::string_view> t, counts;
  bool have_keyword = false;
  while (counts.empty() && lines.next(line)) {
    split_tokens(line, t);
    if (t.empty()) continue;
    std::size_t first = 0;
    if (!have_keyword) {
      if (t[0] == "OFF" || parse_keyword(t[0], header)) {
        have_keyword = true;
        first = 1;
      } else if (t[0].find("OFF") != std::string_view::npos) {
        throw InputError(At{place(file, lines.number())}, "unsupported OFF variant '" +
                         std::string(t[0]) + "' (read: OFF, COFF, NOFF, CNOFF, STOFF)");
      }
      // A file without the keyword starts directly with the counts (allowed by the format).
    }
    if (first < t.size() && t[first] == "BINARY")
      throw InputError(At{place(file, lines.number())}, "binary OFF is not supported");
    counts.assign(t.begin() + first, t.end());
  }
  return counts;
}

// The vertex and face counts of the header, given on line `line`.
void parse_counts(const std::vector<std::string_view>& counts, const std::string& file, std::size_t line,
                  long long& nv, long long& nf) {
  if (counts.size() != 3 && counts.size() != 2)
    throw InputError(At{file + ":" + std::to_string(line)}, "expected the counts 'vertices faces edges'");
  if (!parse_integer(counts[0], nv) || !parse_integer(counts[1], nf) || nv < 0 || nf < 0)
    throw InputError(At{place(file, line)}, "the vertex and face counts must be non-negative integers");
}

// Appends the vertex on line n (tokens t) to `soup`: a position, then as the header says
// a normal, a colour (3 or 4 components) and a texture coordinate.
void read_off_vertex(const std::vector<std::string_view>& t, const OffHeader& header, const std::string& file,
                 std::size_t n, PolygonSoup& soup) {
  const std::size_t want = 3 + (header.normal ? 3 : 0);
  std::size_t extra = t.size() - std::min(t.size(), want);
  const std::size_t st = header.st ? 2 : 0;
  const bool has_color = header.color && extra >= 3 + st;
  if (t.size() < want + st || (header.color && !has_color) ||
      (!header.color && extra != st) || (header.color && extra - st > 4))
    throw InputError(At{place(file, n)}, "expected " + std::to_string(want + st) +
                     (header.color ? " values and a colour" : " values") + " for vertex " +
                     std::to_string(soup.positions.size()) + ", found " + std::to_string(t.size()));
  Eigen::Vector3d p;
  for (int i = 0; i < 3; ++i) p[i] = number_or_throw(t[i], file, n, "coordinate");
  soup.positions.push_back(p);
  if (header.normal) {
    Eigen::Vector3d v;
    for (int i = 0; i < 3; ++i) v[i] = number_or_throw(t[3 + i], file, n, "normal component");
    soup.normals.push_back(v);
  }
  if (has_color) soup.colors.push_back(parse_color(t, want, extra - st, file, n));
  if (header.st) {
    Eigen::Vector2d uv(number_or_throw(t[t.size() - 2], file, n, "texture coordinate"),
                       number_or_throw(t[t.size() - 1], file, n, "texture coordinate"));
    soup.uvs.push_back(uv);
  }
}

// Appends the face of line n with vertices `corners`; per-vertex normals and texture
// coordinates (NOFF, STOFF) become its corners'.
void append_face(const std::vector<std::uint32_t>& corners, const OffHeader& header, std::size_t n,
                 PolygonSoup& soup) {
  for (std::uint32_t v : corners)
    soup.elements.add_corner(v, header.st ? static_cast<std::int32_t>(v) : -1,
                             header.normal ? static_cast<std::int32_t>(v) : -1);
  soup.elements.close(ElementKind::Polygon, -1, n);
}

// The face on line n (tokens t): its vertex count, that many indices below nv, and an
// optional colour (ignored), appended to the soup's elements (`corners`: scratch).
void read_off_face(const std::vector<std::string_view>& t, const OffHeader& header, long long nv,
               const std::string& file, std::size_t n, PolygonSoup& soup, std::vector<std::uint32_t>& corners) {
  long long k;
  if (!parse_integer(t[0], k) || k < 3)
    throw InputError(At{place(file, n)}, "a face starts with its vertex count (3 or more), found '" +
                     std::string(t[0]) + "'");
  if (static_cast<long long>(t.size()) - 1 < k)  // not k + 1: k may be LLONG_MAX
    throw InputError(At{place(file, n)}, "the face lists " + std::to_string(t.size() - 1) + " of its " +
                     std::to_string(k) + " vertices");
  const std::size_t trailing = t.size() - 1 - k;  // optional face colour
  if (trailing != 0 && trailing != 1 && trailing != 3 && trailing != 4)
    throw InputError(At{place(file, n)}, "unexpected values after the face's vertex indices");
  corners.clear();
  for (long long i = 0; i < k; ++i) {
    long long idx;
    if (!parse_integer(t[1 + i], idx) || idx < 0 || idx >= nv)
      throw InputError(At{place(file, n)}, "vertex index '" + std::string(t[1 + i]) +
                       "' is out of range (0.." + std::to_string(nv - 1) + ")");
    corners.push_back(static_cast<std::uint32_t>(idx));
  }
  append_face(corners, header, n, soup);
}

// The fast path for the lines of a plain mesh: a vertex `x y z` (no normal, colour or
// texture coordinates in the header) and a face `k i1 .. ik` without a colour, parsed in
// place. False, having changed nothing, for anything else: the general path then reads
// the line (blank and comment lines included) and gives its error, so both paths read
// the same soup (tests/mesh_io_test.cpp checks this).
bool read_off_vertex_fast(std::string_view line, PolygonSoup& soup) {
  Eigen::Vector3d v;
  if (!fast_numbers_to_end(line.data(), line.data() + line.size(), v.data(), 3)) return false;
  soup.positions.push_back(v);
  return true;
}

bool read_off_face_fast(std::string_view line, const OffHeader& header, long long nv, std::size_t n,
                    PolygonSoup& soup, std::vector<std::uint32_t>& corners) {
  const char* p = skip_blanks(line.data(), line.data() + line.size());
  const char* end = line.data() + line.size();
  long long k = 0;
  if (!fast_integer(p, end, k) || k < 3 || k > static_cast<long long>(line.size())) return false;
  corners.clear();
  for (long long i = 0; i < k; ++i) {
    long long idx = 0;
    p = skip_blanks(p, end);
    if (!fast_integer(p, end, idx) || idx < 0 || idx >= nv) return false;
    corners.push_back(static_cast<std::uint32_t>(idx));
  }
  if (skip_blanks(p, end) != end) return false;
  append_face(corners, header, n, soup);
  return true;
}

// A face record may wrap over several lines (OFF is whitespace-separated, and some
// exporters break long polygons): while t holds fewer indices than its count t[0], the
// next lines' tokens join it. A colour after the indices stays on the record's last line.
void join_wrapped_face(LineScanner& lines, std::vector<std::string_view>& t, std::vector<std::string_view>& more) {
  long long k;
  if (!parse_integer(t[0], k)) return;  // read_off_face names the bad count
  std::string_view line;
  while (static_cast<long long>(t.size()) - 1 < k && lines.next(line)) {
    split_tokens(line, more);
    t.insert(t.end(), more.begin(), more.end());
  }
}

// The next non-blank line's tokens into t; false at the end of the text.
bool next_tokens(LineScanner& lines, std::vector<std::string_view>& t) {
  std::string_view line;
  while (lines.next(line)) {
    split_tokens(line, t);
    if (!t.empty()) return true;
  }
  return false;
}

// The error for a file that ends after `read` of the `promised` vertices or faces.
InputError ends_early(const std::string& file, std::size_t counts_line, std::size_t read, long long promised,
                      const char* what) {
  return InputError(At{place(file, counts_line)}, "the file ends after " + std::to_string(read) + " of the " +
                    std::to_string(promised) + " " + what + " this line promises");
}

// The lines after the counts (`counts`, on line counts_line, views into text): none when
// the text ends on that line.
std::optional<OffBody> body_after(std::string_view text, const std::vector<std::string_view>& counts,
                                  std::size_t counts_line, long long nv, long long nf) {
  if (counts.empty()) return std::nullopt;
  const std::size_t after = static_cast<std::size_t>(counts.back().data() + counts.back().size() - text.data());
  const std::size_t newline = text.find('\n', after);
  if (newline == std::string_view::npos) return std::nullopt;
  return OffBody{text.substr(newline + 1), counts_line, nv, nf};
}

// The parallel path (off_chunks.h) for a plain OFF whose counts, on line counts_line, are
// `counts`, where it is worth trying.
std::optional<PolygonSoup> read_off_in_chunks(std::string_view text, const std::vector<std::string_view>& counts,
                                              std::size_t counts_line, long long nv, long long nf,
                                              const std::function<void()>& release_text) {
  // The first chunk's room for every vertex and face, the others' for what their bytes hold.
  const std::size_t reserved = static_cast<std::size_t>(nv + nf) * kSoupLineBytes + text.size() * kSoupLineBytes / 6;
  if (!worth_reading_in_chunks(text.size(), reserved)) return std::nullopt;
  const std::optional<OffBody> body = body_after(text, counts, counts_line, nv, nf);
  return body ? read_plain_off_in_chunks(*body, omp_get_max_threads(), release_text) : std::nullopt;
}

// The counts' line and values after the header, with the checks read_off makes on them;
// throws as read_off does.
struct OffCounts {
  OffHeader header;
  std::vector<std::string_view> counts;
  std::size_t line = 0;
  long long nv = 0, nf = 0;
};
OffCounts read_counts(std::string_view text, const std::string& file, LineScanner& lines) {
  OffCounts c;
  c.counts = read_header(lines, file, c.header);
  c.line = lines.number();  // named when the file ends early
  parse_counts(c.counts, file, c.line, c.nv, c.nf);
  // Never trust a header: a vertex line takes at least 6 bytes ("0 0 0\n"), a face line 2.
  const long long bytes = static_cast<long long>(text.size());
  if (c.nv > bytes / 6 + 1 || c.nf > bytes / 2 + 1)
    throw InputError(At{place(file, c.line)}, "the counts promise " + std::to_string(c.nv) + " vertices and " +
                     std::to_string(c.nf) + " faces, more than the file's " + std::to_string(bytes) + " bytes can hold");
  return c;
}

PolygonSoup read_off_lines(std::string_view text, const std::string& file, bool fast,
                           const std::function<void()>& release_text = {}) {
  PolygonSoup soup;
  LineScanner lines(text);
  std::vector<std::string_view> t;
  const OffCounts read = read_counts(text, file, lines);
  const OffHeader& header = read.header;
  const std::size_t counts_line = read.line;
  const long long nv = read.nv, nf = read.nf;
  if (fast && !header.normal && !header.color && !header.st)
    if (std::optional<PolygonSoup> chunked = read_off_in_chunks(text, read.counts, counts_line, nv, nf, release_text))
      return std::move(*chunked);
  soup.positions.reserve(nv);
  advise_huge_pages_reserved(soup.positions);
  if (header.normal) soup.normals.reserve(nv);
  soup.normals_per_vertex = header.normal;
  const bool plain = fast && !header.normal && !header.color && !header.st;
  std::string_view line;
  while (static_cast<long long>(soup.positions.size()) < nv) {
    if (!lines.next(line)) throw ends_early(file, counts_line, soup.positions.size(), nv, "vertices");
    if (plain && read_off_vertex_fast(line, soup)) continue;
    split_tokens(line, t);
    if (!t.empty()) read_off_vertex(t, header, file, lines.number(), soup);
  }
  soup.elements.reserve(static_cast<std::size_t>(nf), 3);
  advise_huge_pages_reserved(soup.elements.corners);
  std::vector<std::uint32_t> corners;
  std::vector<std::string_view> more;
  while (static_cast<long long>(soup.elements.size()) < nf) {
    if (!lines.next(line)) throw ends_early(file, counts_line, soup.elements.size(), nf, "faces");
    if (fast && read_off_face_fast(line, header, nv, lines.number(), soup, corners)) continue;
    split_tokens(line, t);
    if (t.empty()) continue;
    const std::size_t first = lines.number();  // a wrapped record is named by its first line
    join_wrapped_face(lines, t, more);
    read_off_face(t, header, nv, file, first, soup, corners);
  }
  if (next_tokens(lines, t)) throw InputError(At{place(file, lines.number())}, "unexpected data after the last face");
  if (release_text) release_text();
  return soup;
}

}  // namespace

PolygonSoup read_off(std::string_view text, const std::string& file) { return read_off_lines(text, file, true); }

PolygonSoup read_off(std::string_view text, const std::string& file, const std::function<void()>& release_text) {
  return read_off_lines(text, file, true, release_text);
}

std::optional<OffBody> plain_off_body(std::string_view text) {
  try {
    LineScanner lines(text);
    const OffCounts read = read_counts(text, "", lines);
    if (read.header.normal || read.header.color || read.header.st) return std::nullopt;
    return body_after(text, read.counts, read.line, read.nv, read.nf);
  } catch (const InputError&) {
    return std::nullopt;
  }
}

PolygonSoup read_off_general(std::string_view text, const std::string& file) {
  return read_off_lines(text, file, false);
}

void write_off(std::ostream& os, const Mesh& mesh, const Eigen::Matrix3Xd* normals, VertexColors colors) {
  TextSink out(os);
  if (colors) out.put('C');
  if (normals) out.put('N');
  out.put("OFF\n");
  out.integer(mesh.num_vertices());
  out.put(' ');
  out.integer(mesh.num_faces());
  out.put(" 0\n");
  const ConstVec3Array p = mesh.positions();
  put_ordered(out, 0, static_cast<std::size_t>(p.cols()), [&](TextSink& line, std::size_t v) {
    const auto i = static_cast<Eigen::Index>(v);
    for (int k = 0; k < 3; ++k) {
      if (k) line.put(' ');
      line.number(p(k, i));
    }
    if (normals)
      for (int k = 0; k < 3; ++k) {
        line.put(' ');
        line.number((*normals)(k, i));
      }
    if (colors) {
      // Integers 0..255, the common COFF form, so readers never guess the scale.
      const Eigen::Vector3f& c = (*colors)[v];
      for (int k = 0; k < 3; ++k) {
        line.put(' ');
        line.integer(std::uint32_t{color_byte(c[k])});
      }
      line.put(" 255");
    }
    line.put('\n');
  });
  const MeshElements& el = mesh.elements();
  put_ordered(out, 0, el.size(), [&](TextSink& line, std::size_t f) {
    if (el.kinds[f] != ElementKind::Polygon) return;  // refused before writing (check_writable)
    line.integer(el.degree(f));
    for (std::uint32_t c = el.begin(f); c < el.end(f); ++c) {
      line.put(' ');
      line.integer(el.corners[c]);
    }
    line.put('\n');
  });
  out.flush();
}

}  // namespace ffd
