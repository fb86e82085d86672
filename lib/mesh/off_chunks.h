// The OFF reader's parallel path for plain files (the `OFF` keyword or none: no normals,
// colours or texture coordinates): the lines after the counts are split into chunks that
// a team parses at once (soup_chunks.h). A line of three numbers is a vertex, a line
// `k i1 .. ik` a face; the file is plain when its vertices all come first and there are as
// many of each as the counts say. Anything else goes back to the serial reader, which gives
// the same soup for plain files and its own message for bad ones.
#pragma once

#include <cstddef>
#include <functional>
#include <optional>
#include <string_view>

#include "mesh/soup.h"

namespace ffd {

/// The plain OFF's counts line and what follows it.
struct OffBody {
  std::string_view text;        // the lines after the counts
  std::size_t counts_line = 0;  // the counts' line number (the body starts on the next)
  long long vertices = 0, faces = 0;
};

/// read_off's soup for a plain OFF whose body is `body`, parsed by `threads` threads, when
/// every line of it is one of:
/// - three numbers (a vertex), the first `body.vertices` records;
/// - `k` >= 3 and k vertex indices below `body.vertices` (a face), the next `body.faces`;
/// - blanks only, or a comment; a comment may also follow a vertex's or a face's values.
///
/// std::nullopt, having thrown nothing, for any other body. Call it only where reserving
/// unused memory is free (reserving_is_free): the first chunk reserves room for every
/// vertex and face the counts promise, the others for what their bytes can hold.
/// `release_text`, when given, is called before the chunks are joined.
std::optional<PolygonSoup> read_plain_off_in_chunks(const OffBody& body, int threads,
                                                    const std::function<void()>& release_text = {});

}  // namespace ffd
