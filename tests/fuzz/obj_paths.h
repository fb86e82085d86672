// The OBJ reader's fast path against its general path (read_obj against
// read_obj_general): on any bytes, the same soup or the same error message. Shared by the
// obj fuzz target and the ctest that replays its corpus.
#pragma once

#include <stdexcept>
#include <string>
#include <string_view>

#include "common/errors.h"
#include "mesh/obj_io.h"

namespace ffd::fuzz {

/// True if the two soups hold the same tables and elements, entry for entry.
inline bool same_soup(const PolygonSoup& a, const PolygonSoup& b) {
  const MeshElements &x = a.elements, &y = b.elements;
  return a.positions == b.positions && a.colors == b.colors && a.uvs == b.uvs && a.normals == b.normals &&
         a.groups == b.groups && a.header == b.header && x.offsets == y.offsets && x.corners == y.corners &&
         x.kinds == y.kinds && x.corner_uvs == y.corner_uvs && x.corner_normals == y.corner_normals &&
         x.groups == y.groups && x.lines == y.lines;
}

/// Reads `bytes` both ways. \throw std::logic_error if the results differ (a soup against
/// an error, two different soups or two different messages); InputError if both refuse
/// the bytes alike.
inline void check_obj_paths_agree(std::string_view bytes) {
  std::string fast_error, general_error;
  PolygonSoup fast, general;
  try {
    fast = read_obj(bytes, "fuzz");
  } catch (const InputError& e) {
    fast_error = e.what();
  }
  try {
    general = read_obj_general(bytes, "fuzz");
  } catch (const InputError& e) {
    general_error = e.what();
  }
  if (fast_error != general_error)
    throw std::logic_error("read_obj says '" + fast_error + "' where read_obj_general says '" + general_error + "'");
  if (!fast_error.empty()) throw InputError(fast_error);
  if (!same_soup(fast, general)) throw std::logic_error("read_obj and read_obj_general read different soups");
}

}  // namespace ffd::fuzz
