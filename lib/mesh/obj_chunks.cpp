#include "mesh/obj_chunks.h"

#include <algorithm>
#include <cstdint>
#include <limits>
#include <vector>

#include "mesh/soup_chunks.h"
#include "mesh/text_lines.h"

namespace ffd {
namespace {

// Reserves room for the `v` and `f` lines `bytes` of text can hold (reserve_for's bound:
// a line takes at least 8 bytes with its newline).
void obj_reserve_lines(std::size_t bytes, PolygonSoup& soup) {
  const std::size_t most = (bytes + 1) / 8;
  reserve_for_lines(soup, most, most);
}

// An `f` line of plain vertex indices (line n of the chunk) into the chunk, a comment
// after them allowed; false at anything else (a `/`, a sign, a zero, fewer than three
// corners). `reach` keeps the most any index goes past the chunk's vertices above the
// face: the chunks before must define more vertices than that.
bool obj_face(std::string_view line, const char* readable, std::size_t n, SoupChunk& chunk, long long& reach) {
  const char* p = line.data() + 1;
  const char* const end = line.data() + line.size();
  MeshElements& el = chunk.soup.elements;
  const auto before = static_cast<long long>(chunk.soup.positions.size());
  std::size_t count = 0;
  for (p = skip_blanks(p, end); p < end && *p != '#'; p = skip_blanks(p, end), ++count) {
    long long raw = 0;
    const auto [next, ec] = decimal(p, end, raw, readable);
    if (ec != std::errc() || next == p || raw <= 0 || (next < end && !blank(*next) && *next != '#')) return false;
    if (raw - 1 > std::numeric_limits<std::uint32_t>::max()) return false;
    reach = std::max(reach, raw - 1 - before);
    el.add_corner(static_cast<std::uint32_t>(raw - 1));
    p = next;
  }
  if (count < 3) return false;
  el.close(ElementKind::Polygon, -1, n);
  return true;
}

// A `v` line of three numbers into the chunk, a comment after them allowed; false at
// anything else.
bool obj_vertex(std::string_view line, SoupChunk& chunk) {
  Eigen::Vector3d v;
  if (!numbers_before_comment(line.data() + 1, line.data() + line.size(), v.data(), 3)) return false;
  chunk.soup.positions.push_back(v);
  return true;
}

// Parses one chunk; stops (chunk.plain false) at its first line the parallel path does
// not take, or soon after another chunk stopped.
void obj_parse_chunk(std::string_view text, const char* readable, const std::atomic<bool>& stopped, SoupChunk& chunk,
                     long long& reach) {
  LineScanner lines(text);
  std::string_view line;
  while (lines.next(line)) {
    if ((lines.number() & 1023) == 0 && stopped.load(std::memory_order_relaxed)) return;
    if (!line.empty() && line.back() == '\\') return;  // a continued line: the serial reader joins it
    if (line.size() > 2 && blank(line[1])) {
      if (line[0] == 'v') {
        if (!obj_vertex(line, chunk)) return;
        continue;
      }
      if (line[0] == 'f' && obj_face(line, readable, lines.number(), chunk, reach)) continue;
    }
    if (!nothing_to_read(line)) return;
  }
  chunk.lines = lines.number();
  chunk.plain = true;
}

// Whether the chunks hold a file the serial reader takes: each face points only at the
// vertices above it, and no more corners than 32-bit offsets count.
bool obj_chunks_valid(const std::vector<SoupChunk>& chunks, const std::vector<long long>& reach) {
  std::size_t vertices = 0, corners = 0;
  for (std::size_t k = 0; k < chunks.size(); ++k) {
    if (reach[k] >= static_cast<long long>(vertices)) return false;
    vertices += chunks[k].soup.positions.size();
    corners += chunks[k].soup.elements.corners.size();
  }
  return corners <= 0xffffffffu;
}

}  // namespace

std::optional<PolygonSoup> read_plain_obj_in_chunks(std::string_view text, int threads,
                                                    const std::function<void()>& release_text) {
  threads = std::max(threads, 1);
  // Two chunks a thread, taken in turn: a file's `v` lines and `f` lines parse at different
  // speeds, and each thread then gets some of both.
  const std::vector<std::string_view> parts = split_at_lines(text, 2 * threads);
  std::vector<SoupChunk> chunks(parts.size());
  std::vector<long long> reach(parts.size(), -1);
  const char* const readable = text.data() + text.size();
  const bool plain = parse_in_team(chunks, threads, [&](std::size_t k, SoupChunk& chunk, const std::atomic<bool>& stopped) {
    obj_reserve_lines(k == 0 ? text.size() : parts[k].size(), chunk.soup);  // chunk 0's holds them all
    obj_parse_chunk(parts[k], readable, stopped, chunk, reach[k]);
  });
  if (!plain || !obj_chunks_valid(chunks, reach)) return std::nullopt;
  if (release_text) release_text();
  if (!join_soup_chunks(chunks, chunks[0].lines, threads)) return std::nullopt;
  return std::move(chunks[0].soup);
}

}  // namespace ffd
