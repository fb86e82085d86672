// The OBJ reader's parallel path for files of plain geometry: nothing but `v x y z` lines,
// `f` lines of vertex indices, comments and blank lines (what scanners, generators and
// meshing tools write, and most of the bytes of large files). The text is split at line
// ends into chunks that a team of threads parses at once; the chunks are then joined in
// order. Anything else sends the file back to the serial reader, which gives the same soup
// for plain files and its own message for bad ones.
#pragma once

#include <cstddef>
#include <functional>
#include <optional>
#include <string_view>

#include "mesh/soup.h"

namespace ffd {

/// read_obj's soup for `text`, parsed in chunks by `threads` threads, when
/// every line is one of:
/// - `v` and three numbers;
/// - `f` and at least three positive vertex indices, each of a vertex defined above it;
/// - blanks only, or a comment (`#` after blanks).
///
/// std::nullopt, having thrown nothing, for any other text: the caller reads it serially.
/// The chunks' arrays hold room for the whole text's lines, so call it only where reserving
/// unused memory is free (reserving_is_free). `release_text`, when given, is called once
/// the chunks are parsed and checked, before they are joined: the text is not needed
/// after it (a mapped file's pages can go) unless joining runs out of memory.
std::optional<PolygonSoup> read_plain_obj_in_chunks(std::string_view text, int threads,
                                                    const std::function<void()>& release_text = {});

}  // namespace ffd
