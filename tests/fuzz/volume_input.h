// The volume readers under fuzzing (fuzz_volume.cpp) and in the ctest replay of their
// corpus: what a reader accepts must write itself back byte for byte with its nodes where
// they were, and a write with every node moved must read back with the same cells.
#pragma once

#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <string_view>

#include "mesh/foam_io.h"
#include "mesh/gmsh_io.h"
#include "mesh/su2_io.h"
#include "mesh/volume_mesh.h"
#include "mesh/vtk_volume_io.h"

namespace ffd::fuzz {

/// Reads `bytes` as `format` ("vtu", "vtk", "msh", "su2", "foam": the five files of a
/// polyMesh in split_foam_bundle's form, whose `points` file is the one written back).
inline VolumeRead read_volume_input(const std::string& format, std::string_view bytes, SharedBytes& written) {
  auto shared = std::make_shared<const FileBytes>(std::string(bytes));
  written = shared;
  if (format == "vtu") return read_vtu(shared, "fuzz.vtu");
  if (format == "vtk") return read_vtk_legacy(shared, "fuzz.vtk");
  if (format == "msh") return read_msh(shared, "fuzz.msh");
  if (format == "su2") return read_su2(shared, "fuzz.su2");
  const FoamFiles files = split_foam_bundle(bytes);
  written = files.points;
  return read_foam_files(files, "fuzz");
}

inline std::string write_volume(const VolumeRead& read, const Eigen::Matrix3Xd& positions) {
  std::ostringstream os;
  read.source.file->write(os, positions);
  return os.str();
}

/// Reads `bytes`; if they are read, checks the writer. \throw InputError as the reader
/// does; std::logic_error when a property fails.
inline void check_volume_round_trip(const std::string& format, std::string_view bytes) {
  SharedBytes original;
  const VolumeRead read = read_volume_input(format, bytes, original);
  if (read.source.cells.offset.size() != read.source.cells.size() + 1)
    throw std::logic_error("the cells' offsets do not match their count");
  if (write_volume(read, read.points) != original->view())
    throw std::logic_error("the unmoved nodes were not written back byte for byte");
  if (read.points.cols() == 0) return;  // nothing to move (read_volume_mesh refuses such a file)
  Eigen::Matrix3Xd moved = read.points;
  moved.array() += 0.5;
  if (read.source.dimension == 2) moved.row(2).setZero();
  const std::string written = write_volume(read, moved);
  SharedBytes again_bytes;
  VolumeRead again;
  if (format == "foam") {  // the written points file in place of the read one
    FoamFiles files = split_foam_bundle(bytes);
    files.points = std::make_shared<const FileBytes>(std::string(written));
    again = read_foam_files(files, "fuzz");
  } else {
    again = read_volume_input(format, written, again_bytes);
  }
  if (again.points.cols() != read.points.cols() || again.source.cells.node != read.source.cells.node ||
      again.source.cells.type != read.source.cells.type)
    throw std::logic_error("the moved nodes' file reads back with other nodes or cells");
}

}  // namespace ffd::fuzz
