// What the text readers' parallel paths share (obj_chunks.h, off_chunks.h): a text split
// at line ends into chunks, the chunks parsed by a team into soups of their own, and the
// soups joined in order into one, as the serial reader would have built it.
#pragma once

#include <atomic>
#include <cstddef>
#include <functional>
#include <string_view>
#include <vector>

#include "mesh/soup.h"

namespace ffd {

/// One chunk's vertices and elements: element corners index the whole file's vertices,
/// element line numbers count from the chunk's first line.
struct SoupChunk {
  PolygonSoup soup;
  std::size_t lines = 0;  // lines in the chunk
  bool plain = false;     // parsed whole: every line was one the parallel path takes
};

/// Whether a reader should try its parallel path on a text of `bytes` whose chunks
/// reserve `reserved` bytes: more than one OpenMP thread, not already inside a team, at
/// least 4 MB of text, and reserving that memory costs nothing unused (reserving_is_free).
bool worth_reading_in_chunks(std::size_t bytes, std::size_t reserved);

/// `text` split at line ends into `count` parts of about equal size (some may be empty).
std::vector<std::string_view> split_at_lines(std::string_view text, int count);

/// Runs `parse(k, chunks[k], stopped)` for every chunk with `threads` threads, each taking the next
/// chunk when done. A parse that throws leaves its chunk not plain; once one chunk is not
/// plain, the rest are skipped (a parse may check `stopped` to stop early). True when
/// every chunk is plain.
bool parse_in_team(std::vector<SoupChunk>& chunks, int threads,
                   const std::function<void(std::size_t, SoupChunk&, const std::atomic<bool>& stopped)>& parse);

/// Joins the chunks in order into chunks[0].soup (which should hold room for all of
/// them), freeing each chunk's arrays as they are copied. Positions, corners and kinds are
/// copied as they are; offsets move on by the corners before, and line numbers by
/// `lines_before_second` (the file's lines before chunks[1]) and the chunks' lines.
/// Meant for soups of plain polygons: corner UVs, normals and groups stay empty. False
/// when memory ran out (nothing leaves the team).
bool join_soup_chunks(std::vector<SoupChunk>& chunks, std::size_t lines_before_second, int threads);

}  // namespace ffd
