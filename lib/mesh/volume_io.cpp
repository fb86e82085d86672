#include "mesh/volume_io.h"

#include <algorithm>
#include <cctype>
#include <cstring>
#include <map>

#include "common/errors.h"
#include "common/numbers.h"
#include "mesh/build_mesh.h"
#include "mesh/foam_io.h"
#include "mesh/gmsh_io.h"
#include "mesh/su2_io.h"
#include "mesh/vtk_volume_io.h"

namespace ffd {
namespace fs = std::filesystem;

std::optional<VolumeFormat> volume_format_of(const fs::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  if (ext == ".vtu") return VolumeFormat::Vtu;
  if (ext == ".vtk") return VolumeFormat::Vtk;
  if (ext == ".msh") return VolumeFormat::Msh;
  if (ext == ".su2") return VolumeFormat::Su2;
  std::error_code ec;
  if (ext.empty() && (path.filename() == "polyMesh" || fs::is_directory(path, ec))) return VolumeFormat::Foam;
  return std::nullopt;
}

namespace {

VolumeRead read_volume(const std::string& path, VolumeFormat format) {
  switch (format) {
    case VolumeFormat::Vtu: return read_vtu(read_shared_file_bytes(path), path);
    case VolumeFormat::Vtk: return read_vtk_legacy(read_shared_file_bytes(path), path);
    case VolumeFormat::Msh: return read_msh(read_shared_file_bytes(path), path);
    case VolumeFormat::Su2: return read_su2(read_shared_file_bytes(path), path);
    case VolumeFormat::Foam: return read_foam(path);
  }
  throw InputError(At{path}, "not a volume mesh format");
}

}  // namespace

namespace {

// A planar mesh (no 3D cell, every z 0: SU2's NDIME=2, a 2D Gmsh mesh) is a surface too:
// its triangles, quads and polygons become the Mesh's faces, so info, render and previews
// see them. Lines and points stay the volume file's alone.
Mesh planar_mesh(const VolumeRead& read, const std::string& path, bool defer_normals) {
  PolygonSoup soup;
  soup.positions.reserve(static_cast<std::size_t>(read.points.cols()));
  for (Eigen::Index i = 0; i < read.points.cols(); ++i) soup.positions.push_back(read.points.col(i));
  const VolumeCells& cells = read.source.cells;
  for (std::size_t c = 0; c < cells.size(); ++c) {
    const std::uint8_t type = cells.type[c];
    if (type == cell_type::kTriangle || type == cell_type::kQuad || type == cell_type::kPolygon)
      soup.elements.add_polygon(std::vector<std::uint32_t>(cells.nodes(c), cells.nodes(c) + cells.degree(c)));
  }
  return build_mesh(std::move(soup), path, defer_normals);
}

}  // namespace

Mesh read_volume_mesh(const std::string& path, VolumeFormat format, bool defer_normals) {
  VolumeRead read = read_volume(path, format);
  if (read.points.cols() == 0) throw InputError(At{path}, "the file has no node");
  Mesh mesh;
  if (read.source.dimension == 2)
    mesh = planar_mesh(read, path, defer_normals);
  else
    mesh.set_vertices(std::move(read.points), /*normals=*/false);
  mesh.set_source(path);
  mesh.set_volume_source(std::make_shared<const VolumeSource>(std::move(read.source)));
  return mesh;
}

void check_volume_writable(const Mesh& mesh, VolumeFormat format, const std::string& path) {
  const VolumeSource* source = mesh.volume_source();
  const std::string wanted = volume_format_name(format);
  if (!source)
    throw InputError(At{path}, "a " + wanted + " output needs a mesh read from one; ffdtool writes volume meshes by "
                               "patching the file they were read from (write this mesh as .obj, .off, .ply, .stl or .gltf)");
  if (source->format != format)
    throw InputError(At{path}, "the mesh was read from a " + volume_format_name(source->format) +
                                   " file and is written back as one; ffdtool does not convert it to " + wanted);
}

namespace {

// Stages a copy of `from` at `to`; returns its size.
std::size_t stage_copy(const fs::path& from, const fs::path& to, std::vector<StagedFile>& files) {
  const SharedBytes bytes = read_shared_file_bytes(from.string());
  fs::create_directories(to.parent_path());
  files.emplace_back(to);
  return files.back().write([&](std::ostream& os) { os.write(bytes->data(), static_cast<std::streamsize>(bytes->size())); });
}

}  // namespace

std::size_t stage_volume_files(const std::string& path, const Mesh& mesh, std::vector<StagedFile>& files) {
  const VolumeSource& source = *mesh.volume_source();
  const auto write_points = [&](std::ostream& os) { source.file->write(os, mesh.position_matrix()); };
  if (source.format != VolumeFormat::Foam) {
    files.emplace_back(fs::path(path));
    return files.back().write(write_points);
  }
  const fs::path folder(path), from(mesh.source());
  fs::create_directories(folder);
  std::size_t total = 0;
  for (const char* name : {"faces", "owner", "neighbour", "boundary"}) total += stage_copy(from / name, folder / name, files);
  for (const std::string& name : source.companion_files) total += stage_copy(from / name, folder / name, files);
  files.emplace_back(folder / "points");
  return total + files.back().write(write_points);
}

std::string unwritten_volume_data(const Mesh& mesh) {
  const VolumeSource* source = mesh.volume_source();
  if (!source) return {};
  std::string lost = "the " + volume_format_name(source->format) + " file's " + format_count(source->cells.size()) +
                     " cells";
  if (!source->markers.empty()) lost += " and " + format_count(source->markers.size()) + " markers";
  return lost + " (only a " + volume_format_name(source->format) + " output holds them; the nodes are written as points)";
}

}  // namespace ffd
