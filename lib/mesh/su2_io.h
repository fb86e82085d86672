// SU2's native mesh format (.su2, ASCII): NDIME, NELEM with the volume elements, NPOIN
// with the nodes, NMARK with each marker's boundary elements. A strict reader with file
// and line in every error; the file is written back by rewriting only the changed nodes'
// coordinates (volume_mesh.h). Anything after the markers (SU2's FFD_NBOX boxes, ...) is
// kept as it is. Multi-zone files (NZONE) are refused by name.
#pragma once

#include <string>

#include "mesh/volume_mesh.h"

namespace ffd {

/// Reads an SU2 mesh. Cells: the NELEM elements, then each marker's elements in marker
/// order (the markers list those). \throw InputError "file:line: ..." on anything malformed.
VolumeRead read_su2(SharedBytes bytes, const std::string& path);

}  // namespace ffd
