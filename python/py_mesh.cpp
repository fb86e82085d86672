// ffdtool.Mesh, ffdtool.read and Mesh.write.
#include "py_mesh.h"

#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include "common/atomic_file.h"
#include "common/errors.h"
#include "mesh/build_mesh.h"
#include "mesh/cell_quality.h"
#include "mesh/mesh_io.h"
#include "script/volume_guard.h"
#include "py_arrays.h"

namespace ffd::py {
namespace {

PyMesh read(const std::filesystem::path& file) {
  const std::string path = file.string();
  PyMesh out{std::make_shared<Scene>(), path};
  pb::gil_scoped_release unlocked;
  out.scene->mesh = read_mesh(path);
  return out;
}

// Issues `message` as an ffdtool.FfdWarning.
void warn(const std::string& message) {
  const pb::object category = pb::module_::import("ffdtool").attr("FfdWarning");
  if (PyErr_WarnEx(category.ptr(), message.c_str(), 1) != 0) throw pb::error_already_set();
}

// Writes as `ffdtool run` writes its output: the file whole or not at all, a glTF's
// buffers and images beside it, file normals carried through the run's warps. A volume
// mesh with inverted cells is refused as the CLI refuses it, unless allowed (then with
// an FfdWarning).
void write(PyMesh& self, const std::filesystem::path& file, bool allow_inverted) {
  const std::string path = file.string();
  const Scene& scene = *self.scene;
  std::string warning;
  {
    pb::gil_scoped_release unlocked;
    const MeshFormat format = mesh_format(path);
    require_output_folder(path, "output");
    check_writable(scene.mesh, format, path);
    if (const VolumeSource* source = scene.mesh.volume_source())
      warning = inverted_cells_warning(scene.mesh, cell_quality(source->cells, scene.mesh.position_matrix()), path,
                                       allow_inverted, "allow_inverted=True");
    for (StagedFile& staged : stage_mesh_files(path, scene.mesh, scene.write_options())) staged.commit();
  }
  if (!warning.empty()) warn(warning);
}

// Appends `faces` (an (m, k) integer array or a sequence of index sequences) to
// `elements` as polygons. \throw InputError at "Mesh(): faces[f]" for an index that is not
// an integer or names no vertex.
void add_faces(const pb::object& faces, std::size_t vertices, MeshElements& elements) {
  if (faces.is_none()) return;
  std::size_t f = 0;
  for (const pb::handle face : faces) {
    const At at{"Mesh(): faces[" + std::to_string(f) + "]"};
    if (!pb::isinstance<pb::iterable>(face)) throw InputError(at, "a face is a sequence of vertex indices");
    for (const pb::handle corner : face) {
      if (!PyIndex_Check(corner.ptr())) throw InputError(at, "vertex indices are integers");
      const long long v = corner.cast<long long>();
      if (v < 0 || static_cast<std::size_t>(v) >= vertices)
        throw InputError(at, "vertex " + std::to_string(v) + " does not exist (the mesh has " +
                                 std::to_string(vertices) + " vertices)");
      elements.add_corner(static_cast<std::uint32_t>(v));
    }
    elements.close(ElementKind::Polygon, -1, 0);
    ++f;
  }
}

PyMesh from_arrays(const Float64Array& vertices, const pb::object& faces) {
  PolygonSoup soup;
  soup.positions = point_list(vertices, "Mesh(): vertices");
  check_finite(soup.positions, "Mesh(): vertices");
  add_faces(faces, soup.positions.size(), soup.elements);
  PyMesh out{std::make_shared<Scene>(), ""};
  pb::gil_scoped_release unlocked;
  out.scene->mesh = build_mesh(std::move(soup), "Mesh()");
  return out;
}

// The polygons: (m, k) when every polygon has k corners, else (offsets, indices).
pb::object faces(const PyMesh& self) {
  const Mesh& mesh = self.scene->mesh;
  std::vector<std::uint32_t> offsets{0}, indices, face;
  for (std::size_t f = 0; f < mesh.num_faces(); ++f) {
    mesh.face_vertices(f, face);
    indices.insert(indices.end(), face.begin(), face.end());
    offsets.push_back(static_cast<std::uint32_t>(indices.size()));
  }
  const std::size_t m = mesh.num_faces();
  const std::size_t k = m ? offsets[1] : 3;
  bool pure = true;
  for (std::size_t f = 0; f < m && pure; ++f) pure = offsets[f + 1] - offsets[f] == k;
  if (pure) return int_array(indices, {static_cast<pb::ssize_t>(m), static_cast<pb::ssize_t>(k)});
  return pb::make_tuple(int_array(offsets, {static_cast<pb::ssize_t>(offsets.size())}),
                        int_array(indices, {static_cast<pb::ssize_t>(indices.size())}));
}

// A table of fixed-size Eigen vectors (UVs, colours) as an (n, size) array, or None when empty.
template <class V>
pb::object table_array(const std::vector<V>& table) {
  if (table.empty()) return pb::none();
  pb::array_t<typename V::Scalar> out({static_cast<pb::ssize_t>(table.size()), static_cast<pb::ssize_t>(V::SizeAtCompileTime)});
  for (std::size_t i = 0; i < table.size(); ++i)
    for (int a = 0; a < V::SizeAtCompileTime; ++a) out.mutable_at(i, a) = table[i][a];
  return out;
}

pb::object corner_indices(const std::vector<std::int32_t>& corner) {
  if (corner.empty()) return pb::none();
  return int_array(corner, {static_cast<pb::ssize_t>(corner.size())});
}

std::string repr(const PyMesh& self) {
  const Mesh& mesh = self.scene->mesh;
  return "<ffdtool.Mesh " + std::to_string(mesh.num_vertices()) + " vertices, " + std::to_string(mesh.num_faces()) +
         " faces" + (self.file.empty() ? "" : " from '" + self.file + "'") + ">";
}

}  // namespace

Mesh run_input(const PyMesh& source) {
  const Scene& scene = *source.scene;
  Mesh mesh = scene.mesh.clone();
  if (scene.stack.size() > 0) {
    scene.stack.bake_copy(mesh);
  } else if (mesh.positions() != mesh.rest_positions()) {
    mesh.rest_positions() = mesh.positions();
    mesh.recompute_rest_normals(true);
  }
  return mesh;
}

void bind_mesh(pb::module_& m) {
  pb::class_<PyMesh>(m, "Mesh", "A polygon mesh (faces, lines and points) with the attributes ffdtool keeps.")
      .def(pb::init(&from_arrays), pb::arg("vertices"), pb::arg("faces") = pb::none(),
           "Mesh(vertices, faces=None): vertices (n, 3) float; faces (m, k) int or a list of polygons "
           "(vertex index lists of any size); none for a point cloud.")
      .def_property_readonly(
          "vertices",
          [](pb::object self) {
            Mesh& mesh = self.cast<PyMesh&>().scene->mesh;
            return vec3_view(mesh.positions().data(), mesh.num_vertices(), self, true);
          },
          "(n, 3) float64 view of the vertices (no copy: writes go through to write() and run()).")
      .def_property_readonly(
          "normals",
          [](pb::object self) {
            Mesh& mesh = self.cast<PyMesh&>().scene->mesh;
            return vec3_view(mesh.normals().data(), mesh.num_vertices(), self, false);
          },
          "(n, 3) float64 read-only view of the unit vertex normals (angle-weighted, carried through the warps).")
      .def_property_readonly("faces", &faces,
                             "The polygons: an (m, k) int64 array when every polygon has k corners, else a tuple "
                             "(offsets (m + 1,), indices): polygon f is indices[offsets[f]:offsets[f + 1]].")
      .def_property_readonly(
          "uvs", [](const PyMesh& s) { return table_array(s.scene->mesh.uvs()); },
          "(t, 2) float64 texture coordinates (the file's table), or None.")
      .def_property_readonly(
          "corner_uvs", [](const PyMesh& s) { return corner_indices(s.scene->mesh.elements().corner_uvs); },
          "Per element corner, in element order, its row of uvs (-1: none), or None.")
      .def_property_readonly(
          "colors", [](const PyMesh& s) { return table_array(s.scene->mesh.colors()); },
          "(n, 3) float32 vertex colours in [0, 1] (a copy), or None.")
      .def_property_readonly("num_vertices", [](const PyMesh& s) { return s.scene->mesh.num_vertices(); },
                             "The number of vertices (rows of vertices).")
      .def_property_readonly("num_faces", [](const PyMesh& s) { return s.scene->mesh.num_faces(); },
                             "The number of polygons (an OBJ's lines and points are not faces).")
      .def_property_readonly("file", [](const PyMesh& s) { return s.file; },
                             "The file the mesh was read from, '' for a mesh made from arrays or by run().")
      .def("write", &write, pb::arg("path"), pb::kw_only(), pb::arg("allow_inverted") = false,
           "Writes the mesh (format from the extension: .obj .off .ply .stl .gltf .glb, or the volume format it was "
           "read from: .vtu .vtk .msh .su2, an OpenFOAM polyMesh folder) as `ffdtool run` writes its output: whole "
           "or not at all, with what the file it was read from carried. A volume mesh with inverted cells raises "
           "InputError, as the CLI refuses it; allow_inverted=True writes it with an FfdWarning.")
      .def("__repr__", &repr);
  m.def("read", &read, pb::arg("path"),
        "Reads a mesh file (.obj .off .ply .stl .gltf .glb; volume meshes: .vtu .vtk .msh .su2, an OpenFOAM "
        "polyMesh folder) as the CLI does. Raises InputError naming the file and place for anything unreadable.");
}

}  // namespace ffd::py
