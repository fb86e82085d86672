// OpenFOAM polyMesh folders (constant/polyMesh): points, faces, owner, neighbour and
// boundary, ASCII or binary. Each OpenFOAM cell becomes a polyhedron (VTK's face stream,
// faces wound outward), each boundary face a triangle, quad or polygon after them, and
// each patch a marker of those. Writing back rewrites the `points` file only; the other
// files of the folder are the caller's to copy (VolumeSource::companion_files).
#pragma once

#include <string>
#include <string_view>

#include "mesh/volume_mesh.h"

namespace ffd {

/// The files of a polyMesh folder, as read.
struct FoamFiles {
  SharedBytes points, faces, owner, neighbour, boundary;
};

/// Reads `folder` (a polyMesh folder: points, faces, owner, neighbour, boundary). A
/// missing file is refused by name, as is a compressed one (points.gz). The folder's
/// other files (cellZones, sets/..., anything) are listed in source.companion_files
/// (paths relative to the folder, '/'-separated, sorted) to be copied as they are.
/// \throw InputError "FILE:LINE: ..." (text) or "FILE: byte N: ..." (binary data).
VolumeRead read_foam(const std::string& folder);

/// The same from the files' bytes (for fuzzing); `folder` names them in messages.
VolumeRead read_foam_files(const FoamFiles& files, const std::string& folder);

/// The fuzz seed form: the five files in one buffer, each preceded by its size as 8 bytes
/// little-endian (points, faces, owner, neighbour, boundary); refuses anything else.
FoamFiles split_foam_bundle(std::string_view bundle);

}  // namespace ffd
