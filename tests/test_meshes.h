// Small synthetic meshes and helpers shared by the tests.
#pragma once

#include <functional>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "mesh/mesh.h"
#include "mesh/soup.h"
#include "warp/parallelepiped.h"
#include "warp/warp.h"

namespace ffd::test {

/// A (n+1)×(n+1) vertex grid over [0,1]² at height z = height(x, y), each square split
/// into two triangles along alternating diagonals (or kept as quads).
PolygonSoup grid_soup(int n, const std::function<double(double, double)>& height = nullptr,
                      bool quads = false);
Mesh grid_mesh(int n, const std::function<double(double, double)>& height = nullptr, bool quads = false);

/// OBJ text of an n × n grid of unit squares on z = 0, vertex (i, j) at (i, j, 0): two
/// triangles per square, or one quad.
std::string grid_obj(int n, bool quads = false);

/// A lattice box that is neither axis-aligned nor rectangular, away from the origin.
Parallelepiped skewed_box();

/// A unit icosphere (radius 1 at the origin) subdivided `levels` times.
Mesh sphere_mesh(int levels);

/// The bundled Stanford bunny (test_data/bunny.obj).
Mesh bunny();

/// Path of a file in test_data/.
std::string data(const std::string& name);

/// A fresh empty folder under the system temp folder, removed when the test binary exits.
std::string temp_folder(const std::string& name);

/// Runs `ffdtool args...` through the shell; returns the exit code, captures stdout and stderr.
int run_tool(const std::string& args, std::string* out = nullptr, std::string* err = nullptr);

/// Reads a whole file ("" if missing).
std::string read_file(const std::string& path);
void write_file(const std::string& path, const std::string& text);

/// Expects `fn` to throw InputError whose message starts with `prefix`, contains every one
/// of `parts` and is one line.
void expect_input_error(const std::function<void()>& fn, const std::string& prefix,
                        const std::vector<std::string>& parts = {});

/// stderr holds exactly one line, "ffdtool: error: ...", mentioning every part.
void expect_one_error_line(const std::string& err, const std::vector<std::string>& parts);

/// A script of `steps` (each a JSON object's text): {"version": 1, "steps": [...]}.
std::string script(const std::vector<std::string>& steps);

/// A script of steps already joined (JSON objects' text, separated by commas):
/// {"version": 1, "steps": [steps]}.
std::string script_with(const std::string& steps);

/// Writes script(steps) to DIR/NAME.json and runs it on `mesh` (default: the bunny) with
/// -o DIR/NAME.off and --stats DIR/NAME.stats.json, quietly; returns the exit code.
int run_script(const std::string& dir, const std::string& name, const std::vector<std::string>& steps,
               std::string* err = nullptr, const std::string& mesh = "");

/// dF/dx at x by central differences of step h along each axis.
Eigen::Matrix3d central_jacobian(const Warp& warp, const Eigen::Vector3d& x, double h);

/// 0, 1, ..., n-1: every point of a scattered deformer, for move_points.
std::vector<std::size_t> all_ids(std::size_t n);

/// Every `stride`th vertex of `mesh` (up to 40) as control points X, their targets Y moved
/// by up to 3% of the diagonal `diag` (seeded by `seed`).
void control_points(const Mesh& mesh, int stride, unsigned seed, std::vector<Eigen::Vector3d>& X,
                    std::vector<Eigen::Vector3d>& Y, double& diag);

/// The folder of CGAL's meshes (data/meshes/ of Debian's libcgal-demo, which
/// scripts/setup.sh installs), extracted once by the build (tests/CMakeLists.txt); ""
/// when it is not there.
std::string cgal_meshes();

/// A mesh of that folder by name ("elephant.off"); "" when it is not there.
std::string cgal_mesh(const std::string& name);

/// Whether the XML file at `xml_path` is a JUnit report as CI systems read it: xmllint
/// (libxml2-utils, which scripts/setup.sh installs) validates it against
/// tests/data/junit.xsd. When not, `why` (if given) gets xmllint's messages.
bool junit_valid(const std::string& xml_path, std::string* why = nullptr);

/// What `xmllint --xpath EXPR` prints for the XML file at `xml_path`, without the final
/// newline ("" on an error): `string(//testsuite/@tests)`, `count(//failure)`.
std::string xpath(const std::string& xml_path, const std::string& expr);

/// The path in single quotes, for run_tool's shell command line.
std::string quoted(const std::string& path);
/// The names of the entries of a folder.
std::set<std::string> files_in(const std::string& dir);
/// Stats without times, memory and what timing chose (keys "ms", "*_ms",
/// "peak_memory_bytes", "frames_on_one_thread"), for comparing runs.
nlohmann::json without_measurements(nlohmann::json j);

/// One polygon of a soup as separate vectors, for tests that read a reader's output
/// face by face; uvs / normals are empty when none of the face's corners has one.
struct SoupFace {
  std::vector<std::uint32_t> vertices;
  std::vector<std::int32_t> uvs, normals;
  std::int32_t group = -1;
  std::size_t line = 0;
};

/// The polygons of `soup` (lines and points left out), in order.
std::vector<SoupFace> soup_faces(const PolygonSoup& soup);

/// Appends a polygon to `soup`; uvs / normals, when given, one per corner.
void add_face(PolygonSoup& soup, const std::vector<std::uint32_t>& vertices,
              const std::vector<std::int32_t>& uvs = {}, const std::vector<std::int32_t>& normals = {},
              std::int32_t group = -1);

}  // namespace ffd::test
