#include "mesh/off_chunks.h"

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <vector>

#include "mesh/soup_chunks.h"
#include "mesh/text_lines.h"

namespace ffd {
namespace {

// Whether p is where a value may end: the line's end, a blank, or a comment.
bool off_value_ends(const char* p, const char* end) { return p == end || blank(*p) || *p == '#'; }

// A line of three numbers (a comment after them allowed) into `v`.
bool off_vertex(std::string_view line, Eigen::Vector3d& v) {
  return numbers_before_comment(line.data(), line.data() + line.size(), v.data(), 3);
}

// A face `k i1 .. ik` (k >= 3, every index below `vertices`, then only blanks or a
// comment) on line n into the chunk; false at anything else.
bool off_face(std::string_view line, const char* readable, long long vertices, std::size_t n, SoupChunk& chunk) {
  const char* const end = line.data() + line.size();
  const char* p = skip_blanks(line.data(), end);
  // An integer at p that ends where a value may: p moves past it.
  const auto integer = [&](long long& value) {
    const std::from_chars_result r = decimal(p, end, value, readable);
    if (r.ec != std::errc() || r.ptr == p || !off_value_ends(r.ptr, end)) return false;
    p = r.ptr;
    return true;
  };
  long long k = 0;
  if (!integer(k) || k < 3 || k > static_cast<long long>(line.size())) return false;
  MeshElements& el = chunk.soup.elements;
  for (long long i = 0; i < k; ++i) {
    p = skip_blanks(p, end);
    long long index = -1;
    if (!integer(index) || index < 0 || index >= vertices) return false;
    el.add_corner(static_cast<std::uint32_t>(index));
  }
  p = skip_blanks(p, end);
  if (p != end && *p != '#') return false;  // a face colour, or more: the serial reader's
  el.close(ElementKind::Polygon, -1, n);
  return true;
}

// Parses one chunk whose first line is line `first_line + 1` of the file; stops (not
// plain) at a line the parallel path does not take, at a vertex after a face, or soon
// after another chunk stopped.
void off_parse_chunk(std::string_view text, const char* readable, long long vertices, std::size_t first_line,
                     const std::atomic<bool>& stopped, SoupChunk& chunk) {
  LineScanner lines(text);
  std::string_view line;
  Eigen::Vector3d v;
  while (lines.next(line)) {
    if ((lines.number() & 1023) == 0 && stopped.load(std::memory_order_relaxed)) return;
    if (off_vertex(line, v)) {
      if (chunk.soup.elements.size() > 0) return;
      chunk.soup.positions.push_back(v);
      continue;
    }
    if (off_face(line, readable, vertices, first_line + lines.number(), chunk)) continue;
    if (!nothing_to_read(line)) return;
  }
  chunk.lines = lines.number();
  chunk.plain = true;
}

// Whether the chunks hold what the counts promise, vertices before faces.
bool off_chunks_valid(const std::vector<SoupChunk>& chunks, const OffBody& body) {
  std::size_t vertices = 0, faces = 0, corners = 0;
  for (const SoupChunk& chunk : chunks) {
    if (!chunk.soup.positions.empty() && faces > 0) return false;  // a vertex after a face
    vertices += chunk.soup.positions.size();
    faces += chunk.soup.elements.size();
    corners += chunk.soup.elements.corners.size();
  }
  return vertices == static_cast<std::size_t>(body.vertices) && faces == static_cast<std::size_t>(body.faces) &&
         corners <= 0xffffffffu;
}

// Reserves a chunk's room: for the first, what the counts promise (its arrays take the
// others'); for the others, the vertex and face lines their bytes can hold (a vertex line
// takes at least 6 bytes, "0 0 0\n", a face 8), as far as the counts allow.
void off_reserve_chunk(std::size_t k, std::size_t bytes, const OffBody& body, PolygonSoup& soup) {
  const auto vertices = static_cast<std::size_t>(body.vertices), faces = static_cast<std::size_t>(body.faces);
  const std::size_t v = k == 0 ? vertices : std::min(vertices, bytes / 6 + 1);
  const std::size_t f = k == 0 ? faces : std::min(faces, bytes / 8 + 1);
  reserve_for_lines(soup, v, f);
}

}  // namespace

std::optional<PolygonSoup> read_plain_off_in_chunks(const OffBody& body, int threads,
                                                    const std::function<void()>& release_text) {
  threads = std::max(threads, 1);
  const std::vector<std::string_view> parts = split_at_lines(body.text, 2 * threads);
  std::vector<SoupChunk> chunks(parts.size());
  const char* const readable = body.text.data() + body.text.size();
  const bool plain = parse_in_team(chunks, threads, [&](std::size_t k, SoupChunk& chunk, const std::atomic<bool>& stopped) {
    off_reserve_chunk(k, parts[k].size(), body, chunk.soup);
    off_parse_chunk(parts[k], readable, body.vertices, k == 0 ? body.counts_line : 0, stopped, chunk);
  });
  if (!plain || !off_chunks_valid(chunks, body)) return std::nullopt;
  if (release_text) release_text();
  if (!join_soup_chunks(chunks, body.counts_line + chunks[0].lines, threads)) return std::nullopt;
  return std::move(chunks[0].soup);
}

}  // namespace ffd
