// Gmsh's MSH format, versions 4.1 and 2.2, ASCII and binary (either byte order): a strict
// reader whose file is written back by patching its node coordinates (volume_mesh.h).
//
// Read: $MeshFormat, $PhysicalNames, $Entities and $PartitionedEntities (4.1: the
// physical groups of each entity), $Nodes (sparse and unordered tags, 4.1 parametric
// coordinates) and $Elements (every element type Gmsh defines with a fixed node count).
// Every other section ($NodeData, $ElementData, $Periodic, comments, unknown ones) is
// skipped. Writing changes node coordinates only: every other byte stays the file's.
// Counts are checked against the bytes left before any allocation.
#pragma once

#include <string>

#include "mesh/volume_mesh.h"

namespace ffd {

/// Reads a Gmsh mesh file, MSH 4.1 or 2.2, ASCII or binary. Cells: every element of the
/// file in its order, as VTK kinds and corner order (Gmsh kinds without a VTK number are
/// kOtherCell with their nodes); markers: one per physical group (dimension, tag), in
/// that order, named by $PhysicalNames or by the tag, with its elements ascending.
/// \throw InputError naming path and place ("FILE:LINE: ..." in ASCII, "FILE: byte N: ..."
/// in binary) on anything malformed, truncated or inconsistent.
VolumeRead read_msh(SharedBytes bytes, const std::string& path);

}  // namespace ffd
