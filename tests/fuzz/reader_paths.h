// The OBJ and OFF readers' fast paths against their general paths (read_obj against
// read_obj_general, read_off against read_off_general): on any bytes, the same soup or
// the same error message; and the OBJ reader's parallel path for plain files
// (read_plain_obj_in_chunks) and the OFF reader's (read_plain_off_in_chunks), which on any
// bytes decline or read what the general path reads. Shared by the obj and off fuzz
// targets and the ctests.
#pragma once

#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>

#include "common/errors.h"
#include "mesh/obj_chunks.h"
#include "mesh/obj_io.h"
#include "mesh/off_io.h"

namespace ffd::fuzz {

/// True if the two soups hold the same tables and elements, entry for entry.
inline bool same_soup(const PolygonSoup& a, const PolygonSoup& b) {
  const MeshElements &x = a.elements, &y = b.elements;
  return a.positions == b.positions && a.colors == b.colors && a.uvs == b.uvs && a.normals == b.normals &&
         a.groups == b.groups && a.header == b.header && x.offsets == y.offsets && x.corners == y.corners &&
         x.kinds == y.kinds && x.corner_uvs == y.corner_uvs && x.corner_normals == y.corner_normals &&
         x.groups == y.groups && x.lines == y.lines;
}

/// Reads `bytes` with `fast` and with `general`. \throw std::logic_error if the results
/// differ (a soup against an error, two different soups or two different messages);
/// InputError if both refuse the bytes alike.
template <class Reader>
void check_paths_agree(std::string_view bytes, Reader fast_reader, Reader general_reader) {
  std::string fast_error, general_error;
  PolygonSoup fast, general;
  try {
    fast = fast_reader(bytes, "fuzz");
  } catch (const InputError& e) {
    fast_error = e.what();
  }
  try {
    general = general_reader(bytes, "fuzz");
  } catch (const InputError& e) {
    general_error = e.what();
  }
  if (fast_error != general_error)
    throw std::logic_error("the fast path says '" + fast_error + "' where the general path says '" + general_error + "'");
  if (!fast_error.empty()) throw InputError(fast_error);
  if (!same_soup(fast, general)) throw std::logic_error("the fast and the general path read different soups");
}

/// Calls `chunked(threads)` for 1 to 3 threads; where it reads a soup, `general(bytes)`
/// must read the same one. \throw std::logic_error if it refuses the bytes or reads
/// another soup.
template <class Chunked>
void check_chunks_agree(std::string_view bytes, Chunked chunked,
                        PolygonSoup (*general_reader)(std::string_view, const std::string&)) {
  for (int threads = 1; threads <= 3; ++threads) {
    const std::optional<PolygonSoup> soup = chunked(threads);
    if (!soup) continue;
    PolygonSoup general;
    try {
      general = general_reader(bytes, "fuzz");
    } catch (const InputError& e) {
      throw std::logic_error(std::string("the parallel path read what the general path refuses: ") + e.what());
    }
    if (!same_soup(*soup, general) || general.obj || soup->obj)  // (the parallel paths keep no statement)
      throw std::logic_error("the parallel and the general path read different soups");
  }
}

/// read_plain_obj_in_chunks on `bytes` against read_obj_general (check_chunks_agree).
inline void check_obj_chunks_agree(std::string_view bytes) {
  check_chunks_agree(bytes, [&](int threads) { return read_plain_obj_in_chunks(bytes, threads); }, &read_obj_general);
}

/// read_plain_off_in_chunks on the body of `bytes` (plain_off_body) against
/// read_off_general (check_chunks_agree).
inline void check_off_chunks_agree(std::string_view bytes) {
  const std::optional<OffBody> body = plain_off_body(bytes);
  if (body)
    check_chunks_agree(bytes, [&](int threads) { return read_plain_off_in_chunks(*body, threads); }, &read_off_general);
}

inline void check_obj_paths_agree(std::string_view bytes) {
  check_obj_chunks_agree(bytes);
  check_paths_agree(bytes, &read_obj, &read_obj_general);
}
inline void check_off_paths_agree(std::string_view bytes) {
  check_off_chunks_agree(bytes);
  check_paths_agree(bytes, &read_off, &read_off_general);
}

}  // namespace ffd::fuzz
