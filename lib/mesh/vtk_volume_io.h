// VTK volume meshes: the XML unstructured grid (.vtu) and the legacy format (.vtk) whose
// DATASET is UNSTRUCTURED_GRID, read strictly and written back by patching the file's
// own bytes (volume_mesh.h).
//
// VTU: one Piece; Points Float32/Float64 × 3; connectivity/offsets/types (and
// faces/faceoffsets for polyhedra) of any integer type; format ascii, binary (base64,
// optionally zlib blocks) or appended (raw or base64, optionally zlib); either byte
// order; header_type UInt32/UInt64. Legacy: versions 1.0 to 5.1, ASCII or BINARY, the
// old CELLS form and 5.1's OFFSETS/CONNECTIVITY. PointData, CellData and FieldData are
// carried as they are. VTK files have no named markers.
#pragma once

#include <cstdint>
#include <string>

#include "mesh/volume_mesh.h"

namespace ffd {

/// Reads a VTK XML UnstructuredGrid (.vtu). \throw InputError naming path and place
/// ("mesh.vtu:12: ...") on malformed or unsupported input (lz4/lzma compression, several
/// Pieces, another VTKFile type).
VolumeRead read_vtu(SharedBytes bytes, const std::string& path);

/// Reads a legacy VTK file whose DATASET is UNSTRUCTURED_GRID (.vtk). \throw InputError
/// naming path and place ("mesh.vtk:7: ..." or "mesh.vtk: byte 812: ...").
VolumeRead read_vtk_legacy(SharedBytes bytes, const std::string& path);

/// The two readers' shared check of one cell as the file gives it: a type VTK defines
/// (kOtherCell, VTK's empty cell, is refused) with the node count it needs. Returns the
/// problem in words, or an empty string.
std::string vtk_cell_problem(std::uint8_t type, std::uint64_t nodes);

/// vtk_cell_problem(type, nodes) is empty: a table look-up, for the loop over every cell.
bool vtk_cell_fits(std::uint8_t type, std::uint64_t nodes);

}  // namespace ffd
