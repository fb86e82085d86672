#include "mesh/soup_chunks.h"

#include <omp.h>

#include <algorithm>
#include <atomic>
#include <cstdint>

#include "common/zeroed_array.h"

namespace ffd {
namespace {

// Appends `from` to `to` and frees `from`: while the chunks are joined, no more than the
// array being copied is held twice.
template <class T>
void append(std::vector<T>& to, std::vector<T>& from) {
  to.insert(to.end(), from.begin(), from.end());
  std::vector<T>().swap(from);
}

// Calls each of `parts` on its own thread of the team; false when one threw.
bool run_sections(int threads, const std::vector<std::function<void()>>& parts) {
  std::atomic<bool> failed{false};
  const auto count = static_cast<long>(parts.size());
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
  for (long k = 0; k < count; ++k) {
    try {
      parts[static_cast<std::size_t>(k)]();
    } catch (...) {
      failed = true;
    }
  }
  return !failed;
}

}  // namespace

bool worth_reading_in_chunks(std::size_t bytes, std::size_t reserved) {
  constexpr std::size_t kChunkedBytes = std::size_t{4} << 20;  // below, one thread reads it in a few ms
  return omp_get_max_threads() > 1 && !omp_in_parallel() && bytes >= kChunkedBytes && reserving_is_free(reserved);
}

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

bool parse_in_team(std::vector<SoupChunk>& chunks, int threads,
                   const std::function<void(std::size_t, SoupChunk&, const std::atomic<bool>& stopped)>& parse) {
  std::atomic<bool> failed{false};
  const auto count = static_cast<long>(chunks.size());
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
  for (long k = 0; k < count; ++k) {
    SoupChunk& chunk = chunks[static_cast<std::size_t>(k)];
    if (failed) continue;  // another chunk is not plain: the file goes to the serial reader
    try {
      parse(static_cast<std::size_t>(k), chunk, failed);
    } catch (...) {
      chunk.plain = false;
    }
    if (!chunk.plain) failed = true;
  }
  return !failed;
}

bool join_soup_chunks(std::vector<SoupChunk>& chunks, std::size_t lines_before_second, int threads) {
  MeshElements& out = chunks[0].soup.elements;
  std::vector<Eigen::Vector3d>& positions = chunks[0].soup.positions;
  const std::size_t first_corners = out.corners.size();
  const auto later = [&](auto each) {
    for (std::size_t k = 1; k < chunks.size(); ++k) each(chunks[k]);
  };
  return run_sections(
      threads,
      {[&] { later([&](SoupChunk& c) { append(positions, c.soup.positions); }); },
       [&] {
         later([&](SoupChunk& c) {
           append(out.corners, c.soup.elements.corners);
           append(out.kinds, c.soup.elements.kinds);
         });
       },
       [&] {
         std::size_t corners = first_corners;
         later([&](SoupChunk& c) {
           std::vector<std::uint32_t>& offsets = c.soup.elements.offsets;
           for (std::size_t e = 1; e < offsets.size(); ++e)
             out.offsets.push_back(static_cast<std::uint32_t>(corners + offsets[e]));
           corners = out.offsets.back();  // the corners so far (the section above frees the chunk's)
           std::vector<std::uint32_t>().swap(offsets);
         });
       },
       [&] {
         std::size_t lines = lines_before_second;
         later([&](SoupChunk& c) {
           for (const std::uint32_t line : c.soup.elements.lines)
             out.lines.push_back(static_cast<std::uint32_t>(std::min<std::size_t>(lines + line, 0xffffffffu)));
           lines += c.lines;
           std::vector<std::uint32_t>().swap(c.soup.elements.lines);
         });
       }});
}

}  // namespace ffd
