#include "mesh/mesh_io.h"

#include <algorithm>
#include <cctype>
#include <cstring>
#include <exception>
#include <memory>
#include <optional>
#include <sstream>

#include "common/atomic_file.h"
#include "common/errors.h"
#include "common/file_bytes.h"
#include "common/numbers.h"
#include "mesh/build_mesh.h"
#include "mesh/obj_source.h"
#include "mesh/off_io.h"
#include "mesh/ply_io.h"
#include "mesh/ply_source.h"
#include "mesh/ply_stl_io.h"
#include "mesh/stl_io.h"
#include "mesh/text_encoding.h"
#include "mesh/volume_io.h"
#include "mesh/vertex_colors.h"

namespace ffd {

namespace {

std::optional<MeshFormat> format_of(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  if (ext == ".obj") return MeshFormat::Obj;
  if (ext == ".off") return MeshFormat::Off;
  if (ext == ".ply") return MeshFormat::Ply;
  if (ext == ".stl") return MeshFormat::Stl;
  if (ext == ".gltf") return MeshFormat::Gltf;
  if (ext == ".glb") return MeshFormat::Glb;
  if (const std::optional<VolumeFormat> volume = volume_format_of(path)) {
    switch (*volume) {
      case VolumeFormat::Vtu: return MeshFormat::Vtu;
      case VolumeFormat::Vtk: return MeshFormat::Vtk;
      case VolumeFormat::Msh: return MeshFormat::Msh;
      case VolumeFormat::Su2: return MeshFormat::Su2;
      case VolumeFormat::Foam: return MeshFormat::Foam;
    }
  }
  return std::nullopt;
}

}  // namespace

MeshFormat mesh_format(const std::filesystem::path& path) {
  if (const std::optional<MeshFormat> format = format_of(path)) return *format;
  throw InputError(path.string() + ": unknown mesh format '" + path.extension().string() +
                   "' (ffdtool reads and writes .obj, .off, .ply, .stl, .gltf, .glb, the volume meshes .vtu, .vtk, "
                   ".msh, .su2, and OpenFOAM polyMesh folders: an existing folder, or a path ending in polyMesh)");
}

bool has_mesh_extension(const std::filesystem::path& path) {
  const std::optional<MeshFormat> format = format_of(path);
  return format && format != MeshFormat::Foam;
}

std::optional<VolumeFormat> volume_format(MeshFormat format) {
  switch (format) {
    case MeshFormat::Vtu: return VolumeFormat::Vtu;
    case MeshFormat::Vtk: return VolumeFormat::Vtk;
    case MeshFormat::Msh: return VolumeFormat::Msh;
    case MeshFormat::Su2: return VolumeFormat::Su2;
    case MeshFormat::Foam: return VolumeFormat::Foam;
    default: return std::nullopt;
  }
}

namespace {

// Per-vertex normals for formats that hold one normal per vertex: each vertex's file
// normal carried into deformed space (vertex_file_normals); vertices without a file
// normal get their current normal.
Eigen::Matrix3Xd per_vertex_normals(const Mesh& mesh, const NormalTransform& transform) {
  Eigen::Matrix3Xd out = mesh.normals();
  const VertexFileNormals file = vertex_file_normals(mesh, transform);
  for (std::size_t v = 0; v < file.has.size(); ++v)
    if (file.has[v]) out.col(static_cast<Eigen::Index>(v)) = file.value[v];
  return out;
}

// Stages `file`'s bytes at `at`; returns their count.
std::size_t stage_companion(const std::filesystem::path& at, const CompanionFile& file, std::vector<StagedFile>& files) {
  files.emplace_back(at);
  return files.back().write([&](std::ostream& os) {
    os.write(reinterpret_cast<const char*>(file.bytes.data()), static_cast<std::streamsize>(file.bytes.size()));
  });
}

// Stages a copy of each external image of a glTF source beside `target` when it goes to
// another folder, so the written file's image URIs still resolve; returns the bytes.
std::size_t stage_gltf_images(const std::filesystem::path& target, const Mesh& mesh, std::vector<StagedFile>& files) {
  const std::filesystem::path from = gltf_folder(mesh);
  const std::filesystem::path to = std::filesystem::absolute(target).parent_path().lexically_normal();
  if (from.empty() || from == to) return 0;
  std::size_t total = 0;
  for (const CompanionFile& c : gltf_image_files(mesh)) {
    std::filesystem::create_directories((to / c.name).parent_path());
    total += stage_companion(to / c.name, c, files);
  }
  return total;
}

}  // namespace

Mesh read_mesh(const std::string& path, bool defer_normals) {
  const MeshFormat format = mesh_format(path);
  if (const std::optional<VolumeFormat> volume = volume_format(format)) return read_volume_mesh(path, *volume, defer_normals);
  const FileBytes bytes = read_file_bytes(path);
  std::string_view text = bytes.view();
  // A text format (and a PLY's header) must be ASCII or UTF-8; a binary STL's 80-byte
  // header and a GLB are bytes.
  if (format != MeshFormat::Glb && !(format == MeshFormat::Stl && stl_is_binary(text))) {
    refuse_wide_text(text, path);
    text = without_utf8_bom(text);
  }
  PolygonSoup soup;
  switch (format) {
    case MeshFormat::Obj:
      soup = read_obj(text, path, [&bytes] { bytes.release_pages(); });
      break;
    case MeshFormat::Off:
      soup = read_off(text, path, [&bytes] { bytes.release_pages(); });
      break;
    case MeshFormat::Ply:
      soup = read_ply(text, path);
      break;
    case MeshFormat::Stl:
      soup = read_stl(text, path);
      break;
    case MeshFormat::Gltf:
    case MeshFormat::Glb:
      return read_gltf(text, path, format == MeshFormat::Glb);
    default:
      break;  // the volume formats, read above
  }
  // Nothing to deform, and nothing a step could write back: not a mesh.
  if (soup.positions.empty()) throw InputError(At{path}, "the file has no vertex");
  bytes.release_pages();  // parsed: the file's pages need not stay beside the mesh being built
  return build_mesh(std::move(soup), path, defer_normals);
}

std::pair<Mesh, Mesh> read_mesh_pair(const std::string& a, const std::string& b) {
  std::pair<Mesh, Mesh> out;
  std::exception_ptr error[2];
#pragma omp parallel sections num_threads(2)
  {
#pragma omp section
    try {
      out.first = read_mesh(a);
    } catch (...) {
      error[0] = std::current_exception();
    }
#pragma omp section
    try {
      out.second = read_mesh(b);
    } catch (...) {
      error[1] = std::current_exception();
    }
  }
  for (const std::exception_ptr& e : error)
    if (e) std::rethrow_exception(e);
  return out;
}

void check_writable(const Mesh& mesh, MeshFormat format, const std::string& path) {
  if (const std::optional<VolumeFormat> volume = volume_format(format)) return check_volume_writable(mesh, *volume, path);
  if (format == MeshFormat::Obj) return;
  const bool gltf = format == MeshFormat::Gltf || format == MeshFormat::Glb;
  if (gltf && mesh.gltf_scene()) return;  // written in its own structure
  const std::size_t lines = mesh.elements().count(ElementKind::Line);
  const std::size_t points = mesh.elements().count(ElementKind::Point);
  if (lines + points == 0) return;
  const char* name = gltf ? "a glTF written from another format" : format == MeshFormat::Off ? "OFF"
                     : format == MeshFormat::Ply ? "PLY" : "STL";
  throw InputError(At{path}, std::string(name) + " holds faces only, and the mesh has " + std::to_string(lines) +
                                 " line and " + std::to_string(points) +
                                 " point elements (OBJ l and p); save it as .obj to keep them");
}

std::vector<std::string> uninterpreted_data(const Mesh& mesh) {
  std::vector<std::string> notes;
  if (const ObjSource* obj = mesh.obj_source_as_read())
    for (const auto& [key, count] : obj->keywords)
      notes.push_back(format_count(count) + " OBJ '" + key + "' statement" + (count > 1 ? "s are" : " is") +
                      " not interpreted; an OBJ output writes " + (count > 1 ? "them" : "it") + " back in place");
  for (const std::string& note : gltf_warnings(mesh)) notes.push_back(note);
  return notes;
}

namespace {

// What only an OBJ output carries of the OBJ file the mesh was read from.
std::string unwritten_obj_data(const Mesh& mesh, MeshFormat format) {
  const ObjSource* obj = mesh.obj_source_as_read();
  if (!obj || (format == MeshFormat::Obj && mesh.obj_source())) return {};
  std::string lost;
  for (const auto& [key, count] : obj->keywords) lost += (lost.empty() ? "the OBJ file's '" : ", '") + key + "'";
  if (!lost.empty()) lost += " statements";
  if (!obj->w.empty()) lost += lost.empty() ? "the OBJ file's w components" : " and w components";
  return lost + (format == MeshFormat::Obj ? " (the steps changed the connectivity)" : " (only an OBJ holds them)");
}

}  // namespace

std::string unwritten_data(const Mesh& mesh, MeshFormat format) {
  if (mesh.volume_source() && !volume_format(format)) return unwritten_volume_data(mesh) + " are not written";
  std::string lost = unwritten_obj_data(mesh, format);
  const PlySource* ply = mesh.ply_source_as_read();
  const bool faithful = format == MeshFormat::Ply && mesh.ply_source();
  if (ply && !faithful) {
    const std::vector<std::string> names = ply->carried_only_here();
    std::string ply_lost;
    for (std::size_t i = 0; i < names.size(); ++i) ply_lost += (i ? ", " : "the PLY file's ") + names[i];
    if (!ply_lost.empty())
      lost += ply_lost + (format == MeshFormat::Ply ? " (the steps changed the connectivity)" : " (only a PLY holds them)");
  }
  if (format == MeshFormat::Ply && !faithful && mesh.has_uvs() && vertex_uvs(mesh).empty())
    lost += std::string(lost.empty() ? "" : "; ") + "the UVs (a vertex's corners have different ones, and PLY holds one per vertex)";
  return lost.empty() ? lost : lost + " are not written";
}

void write_mesh(std::ostream& os, MeshFormat format, const Mesh& mesh, const WriteOptions& options) {
  Eigen::Matrix3Xd normals;
  if (mesh.has_file_normals() && format != MeshFormat::Obj && format != MeshFormat::Stl)
    normals = per_vertex_normals(mesh, options.transform_normal);
  const Eigen::Matrix3Xd* vertex_normals = normals.size() ? &normals : nullptr;
  const std::vector<Eigen::Vector3f> own = options.colors.empty() ? color_array(mesh) : std::vector<Eigen::Vector3f>();
  const VertexColors colors = !options.colors.empty() ? &options.colors : own.empty() ? nullptr : &own;
  const bool binary = options.encoding == WriteOptions::Encoding::Binary ||
                      (options.encoding == WriteOptions::Encoding::Auto && mesh.source_binary());
  switch (format) {
    case MeshFormat::Obj:
      write_obj(os, mesh, options.transform_normal, colors);
      break;
    case MeshFormat::Off:
      write_off(os, mesh, vertex_normals, colors);
      break;
    case MeshFormat::Ply:
      if (mesh.ply_source()) write_ply_source(os, mesh, vertex_normals, options.colors.empty() ? nullptr : &options.colors, binary);
      else write_ply(os, mesh, vertex_normals, colors, binary);
      break;
    case MeshFormat::Stl:
      write_stl(os, mesh, binary);
      break;
    case MeshFormat::Gltf:
    case MeshFormat::Glb:
      write_gltf(os, mesh, options.transform_normal, format == MeshFormat::Glb);
      break;
    default:  // a volume format (check_writable first): the file patched; OpenFOAM's `points`
      mesh.volume_source()->file->write(os, mesh.position_matrix());
      break;
  }
}

std::vector<StagedFile> stage_mesh_files(const std::string& path, const Mesh& mesh, const WriteOptions& options,
                                         std::size_t* bytes) {
  const std::filesystem::path target(path);
  const MeshFormat format = mesh_format(target);
  check_writable(mesh, format, path);
  std::vector<StagedFile> files;
  std::size_t total = 0;
  if (volume_format(format)) {
    total = stage_volume_files(path, mesh, files);
    if (bytes) *bytes = total;
    return files;
  }
  if (format == MeshFormat::Gltf || format == MeshFormat::Glb) total = stage_gltf_images(target, mesh, files);
  if (format != MeshFormat::Gltf) {
    files.emplace_back(target);
    total += files.back().write([&](std::ostream& os) { write_mesh(os, format, mesh, options); });
    if (bytes) *bytes = total;
    return files;
  }
  std::vector<CompanionFile> companions;
  std::ostringstream main;
  write_gltf(main, mesh, options.transform_normal, false, target.stem().string(), &companions);
  for (const CompanionFile& c : companions) {
    const std::filesystem::path at = target.parent_path() / c.name;
    const std::filesystem::path normal = std::filesystem::absolute(at).lexically_normal();
    if (const GltfScene* scene = mesh.gltf_scene(); scene && gltf_reads_file(*scene, normal))
      throw InputError(At{path}, "its buffer " + at.string() + " would replace the input's; choose another name");
    total += stage_companion(at, c, files);
  }
  const std::string json = main.str();
  files.emplace_back(target);
  total += files.back().write([&](std::ostream& os) { os << json; });
  if (bytes) *bytes = total;
  return files;
}

void write_mesh(const std::string& path, const Mesh& mesh, const WriteOptions& options) {
  require_output_folder(path, "output");
  for (StagedFile& f : stage_mesh_files(path, mesh, options)) f.commit();
}

}  // namespace ffd
