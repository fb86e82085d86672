#include "mesh/obj_chunks.h"

#include <omp.h>

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <functional>
#include <limits>
#include <vector>

#include "mesh/text_lines.h"

namespace ffd {
namespace {

// What one chunk holds once parsed: its vertices and faces (corners already 0-based
// indices into the whole file's vertices, line numbers counted from the chunk's first
// line), how many lines it has, and how far its faces reach past the vertices defined
// before them inside the chunk: the chunks before must define more vertices than that.
struct Chunk {
  PolygonSoup soup;
  std::size_t lines = 0;
  long long reach = -1;  // max over corners of (index - vertices of this chunk above the face)
  bool plain = false;
};

// Reserves room for the `v` and `f` lines `bytes` of text can hold (reserve_for's bound:
// a line takes at least 8 bytes with its newline).
void reserve_lines(std::size_t bytes, PolygonSoup& soup) {
  const std::size_t most = (bytes + 1) / 8;
  soup.positions.reserve(most);
  soup.elements.reserve(most, 3);
  soup.elements.lines.reserve(most);
}

// The text split at line ends into `count` parts of about equal size (some may be empty).
std::vector<std::string_view> split_at_lines(std::string_view text, int count) {
  std::vector<std::string_view> parts;
  std::size_t start = 0;
  for (int k = 1; k <= count; ++k) {
    std::size_t end = k == count ? text.size() : std::max(start, text.size() / count * k);
    if (end < text.size()) {
      const std::size_t newline = text.find('\n', end);
      end = newline == std::string_view::npos ? text.size() : newline + 1;
    }
    parts.push_back(text.substr(start, end - start));
    start = end;
  }
  return parts;
}

// An `f` line of plain vertex indices (line n of the chunk) into the chunk, a comment
// after them allowed; false at anything else (a `/`, a sign, a zero, fewer than three
// corners).
bool plain_face(std::string_view line, const char* readable, std::size_t n, Chunk& chunk) {
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
    chunk.reach = std::max(chunk.reach, raw - 1 - before);
    el.add_corner(static_cast<std::uint32_t>(raw - 1));
    p = next;
  }
  if (count < 3) return false;
  el.close(ElementKind::Polygon, -1, n);
  return true;
}

// A `v` line of three numbers into the chunk, a comment after them allowed; false at
// anything else.
bool plain_vertex(std::string_view line, Chunk& chunk) {
  Eigen::Vector3d v;
  if (!fast_numbers_to_end(line.data() + 1, line.data() + line.size(), v.data(), 3)) {
    const std::size_t hash = line.find('#');  // rare: only then look for a comment
    if (hash == std::string_view::npos || !fast_numbers_to_end(line.data() + 1, line.data() + hash, v.data(), 3))
      return false;
  }
  chunk.soup.positions.push_back(v);
  return true;
}

// Whether the line holds nothing to read: blanks, then the end or a comment.
bool nothing_to_read(std::string_view line) {
  const char* p = skip_blanks(line.data(), line.data() + line.size());
  return p == line.data() + line.size() || *p == '#';
}

// Parses one chunk; stops (chunk.plain false) at its first line the parallel path does not
// take, or soon after another chunk stopped (`stop`).
void parse_chunk(std::string_view text, const char* readable, std::atomic<bool>& stop, Chunk& chunk) {
  LineScanner lines(text);
  std::string_view line;
  while (lines.next(line)) {
    if ((lines.number() & 1023) == 0 && stop.load(std::memory_order_relaxed)) return;
    if (!line.empty() && line.back() == '\\') return;  // a continued line: the serial reader joins it
    if (line.size() > 2 && blank(line[1])) {
      if (line[0] == 'v') {
        if (!plain_vertex(line, chunk)) return;
        continue;
      }
      if (line[0] == 'f' && plain_face(line, readable, lines.number(), chunk)) continue;
    }
    if (!nothing_to_read(line)) return;
  }
  chunk.lines = lines.number();
  chunk.plain = true;
}

// Whether the chunks hold a file the serial reader takes: each face points only at the
// vertices above it, and no more corners than 32-bit offsets count.
bool chunks_valid(const std::vector<Chunk>& chunks) {
  std::size_t vertices = 0, corners = 0;
  for (const Chunk& chunk : chunks) {
    if (chunk.reach >= static_cast<long long>(vertices)) return false;
    vertices += chunk.soup.positions.size();
    corners += chunk.soup.elements.corners.size();
  }
  return corners <= 0xffffffffu;
}

// Appends `from` to `to` and frees `from`: while the chunks are joined, no more than the
// array being copied is held twice.
template <class T>
void append(std::vector<T>& to, std::vector<T>& from) {
  to.insert(to.end(), from.begin(), from.end());
  std::vector<T>().swap(from);
}

// Calls each of `parts` on its own thread of the team; false when one threw (nothing
// leaves the team).
template <class... Part>
bool run_sections(int threads, const Part&... parts) {
  const std::function<void()> all[] = {parts...};
  const long count = static_cast<long>(sizeof...(parts));
  std::atomic<bool> failed{false};
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
  for (long k = 0; k < count; ++k) {
    try {
      all[k]();
    } catch (...) {
      failed = true;
    }
  }
  return !failed;
}

// Joins the chunks in order into chunk 0's soup, each array by one thread of the team:
// positions, corners and kinds as they are, offsets and line numbers moved on by the
// corners and lines of the chunks before. False when memory ran out.
bool join_chunks(std::vector<Chunk>& chunks, int threads) {
  MeshElements& out = chunks[0].soup.elements;
  std::vector<Eigen::Vector3d>& positions = chunks[0].soup.positions;
  const std::size_t first_corners = out.corners.size(), first_lines = chunks[0].lines;
  return run_sections(
      threads,
      [&] {
        for (std::size_t k = 1; k < chunks.size(); ++k) append(positions, chunks[k].soup.positions);
      },
      [&] {
        for (std::size_t k = 1; k < chunks.size(); ++k) {
          append(out.corners, chunks[k].soup.elements.corners);
          append(out.kinds, chunks[k].soup.elements.kinds);
        }
      },
      [&] {
        std::size_t corners = first_corners;
        for (std::size_t k = 1; k < chunks.size(); ++k) {
          std::vector<std::uint32_t>& offsets = chunks[k].soup.elements.offsets;
          for (std::size_t e = 1; e < offsets.size(); ++e) out.offsets.push_back(static_cast<std::uint32_t>(corners + offsets[e]));
          corners = out.offsets.back();  // the corners so far (the corners section frees the chunk's own)
          std::vector<std::uint32_t>().swap(offsets);
        }
      },
      [&] {
        std::size_t lines = first_lines;
        for (std::size_t k = 1; k < chunks.size(); ++k) {
          std::vector<std::uint32_t>& from = chunks[k].soup.elements.lines;
          for (const std::uint32_t line : from)
            out.lines.push_back(static_cast<std::uint32_t>(std::min<std::size_t>(lines + line, 0xffffffffu)));
          lines += chunks[k].lines;
          std::vector<std::uint32_t>().swap(from);
        }
      });
}

}  // namespace

std::optional<PolygonSoup> read_plain_obj_in_chunks(std::string_view text, int threads,
                                                    const std::function<void()>& release_text) {
  threads = std::max(threads, 1);
  // Two chunks a thread, taken in turn: a file's `v` lines and `f` lines parse at different
  // speeds, and each thread then gets some of both.
  const std::vector<std::string_view> parts = split_at_lines(text, 2 * threads);
  std::vector<Chunk> parsed(parts.size());
  std::atomic<bool> stop{false};
  const char* const readable = text.data() + text.size();
  const auto count = static_cast<long>(parts.size());
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
  for (long k = 0; k < count; ++k) {
    Chunk& chunk = parsed[static_cast<std::size_t>(k)];
    try {  // nothing may leave the team: a chunk that cannot be held is not plain
      reserve_lines(k == 0 ? text.size() : parts[static_cast<std::size_t>(k)].size(), chunk.soup);
      parse_chunk(parts[static_cast<std::size_t>(k)], readable, stop, chunk);
    } catch (...) {
      chunk.plain = false;
    }
    if (!chunk.plain) stop = true;
  }
  if (stop || !chunks_valid(parsed)) return std::nullopt;
  if (release_text) release_text();
  if (!join_chunks(parsed, threads)) return std::nullopt;
  return std::move(parsed[0].soup);
}

}  // namespace ffd
