#include "test_meshes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <sstream>
#include <sys/wait.h>
#include <unistd.h>

#include "common/errors.h"
#include "mesh/build_mesh.h"
#include "mesh/mesh_io.h"

namespace ffd::test {
namespace fs = std::filesystem;

PolygonSoup grid_soup(int n, const std::function<double(double, double)>& height, bool quads) {
  PolygonSoup soup;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      const double x = static_cast<double>(i) / n, y = static_cast<double>(j) / n;
      soup.positions.emplace_back(x, y, height ? height(x, y) : 0.0);
    }
  const auto id = [n](int i, int j) { return static_cast<std::uint32_t>(j * (n + 1) + i); };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const std::uint32_t a = id(i, j), b = id(i + 1, j), c = id(i + 1, j + 1), d = id(i, j + 1);
      if (quads) {
        soup.elements.add_polygon({a, b, c, d});
      } else if ((i + j) % 2 == 0) {
        soup.elements.add_polygon({a, b, c});
        soup.elements.add_polygon({a, c, d});
      } else {
        soup.elements.add_polygon({a, b, d});
        soup.elements.add_polygon({b, c, d});
      }
    }
  return soup;
}

Mesh grid_mesh(int n, const std::function<double(double, double)>& height, bool quads) {
  return build_mesh(grid_soup(n, height, quads), "grid");
}

Mesh sphere_mesh(int levels) {
  PolygonSoup soup;
  const double t = (1 + std::sqrt(5.0)) / 2;
  const double raw[12][3] = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                             {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  for (const auto& p : raw) soup.positions.push_back(Eigen::Vector3d(p[0], p[1], p[2]).normalized());
  std::vector<std::array<std::uint32_t, 3>> tris = {
      {0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
      {3, 9, 4}, {3, 4, 2}, {3, 2, 6}, {3, 6, 8}, {3, 8, 9}, {4, 9, 5}, {2, 4, 11}, {6, 2, 10}, {8, 6, 7}, {9, 8, 1}};
  for (int l = 0; l < levels; ++l) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> mid;
    const auto midpoint = [&](std::uint32_t a, std::uint32_t b) {
      auto key = std::minmax(a, b);
      auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      soup.positions.push_back((soup.positions[a] + soup.positions[b]).normalized());
      const auto id = static_cast<std::uint32_t>(soup.positions.size() - 1);
      mid[key] = id;
      return id;
    };
    std::vector<std::array<std::uint32_t, 3>> next;
    for (const auto& f : tris) {
      const std::uint32_t ab = midpoint(f[0], f[1]), bc = midpoint(f[1], f[2]), ca = midpoint(f[2], f[0]);
      next.push_back({f[0], ab, ca});
      next.push_back({f[1], bc, ab});
      next.push_back({f[2], ca, bc});
      next.push_back({ab, bc, ca});
    }
    tris = next;
  }
  for (const auto& f : tris) soup.elements.add_polygon({f[0], f[1], f[2]});
  return build_mesh(soup, "sphere");
}

std::string data(const std::string& name) { return std::string(FFD_TEST_DATA) + "/" + name; }

Mesh bunny() { return read_mesh(data("bunny.obj")); }

namespace {
struct TempRoot {
  fs::path root;
  TempRoot() {
    root = fs::temp_directory_path() / ("ffd_tests_" + std::to_string(::getpid()));
    fs::create_directories(root);
  }
  ~TempRoot() {
    std::error_code ec;
    fs::remove_all(root, ec);
  }
};
TempRoot& temp_root() {
  static TempRoot root;
  return root;
}
}  // namespace

std::string temp_folder(const std::string& name) {
  const fs::path p = temp_root().root / name;
  fs::remove_all(p);
  fs::create_directories(p);
  return p.string();
}

std::string read_file(const std::string& path) {
  std::ifstream is(path, std::ios::binary);
  std::stringstream ss;
  ss << is.rdbuf();
  return ss.str();
}

void write_file(const std::string& path, const std::string& text) {
  std::ofstream os(path, std::ios::binary);
  os << text;
}

int run_tool(const std::string& args, std::string* out, std::string* err) {
  const std::string dir = temp_folder("run_tool");
  const std::string out_path = dir + "/stdout", err_path = dir + "/stderr";
  const std::string command = std::string(FFD_TOOL) + " " + args + " >" + out_path + " 2>" + err_path;
  const int status = std::system(command.c_str());
  if (out) *out = read_file(out_path);
  if (err) *err = read_file(err_path);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::string grid_obj(int n, bool quads) {
  std::string s;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) s += "v " + std::to_string(i) + " " + std::to_string(j) + " 0\n";
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const std::string a = std::to_string(j * (n + 1) + i + 1), b = std::to_string(j * (n + 1) + i + 2),
                        c = std::to_string((j + 1) * (n + 1) + i + 2), d = std::to_string((j + 1) * (n + 1) + i + 1);
      s += quads ? "f " + a + " " + b + " " + c + " " + d + "\n" : "f " + a + " " + b + " " + c + "\nf " + a + " " + c + " " + d + "\n";
    }
  return s;
}

void expect_input_error(const std::function<void()>& fn, const std::string& prefix,
                        const std::vector<std::string>& parts) {
  try {
    fn();
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.rfind(prefix, 0), 0u) << "message '" << what << "' does not start with '" << prefix << "'";
    for (const std::string& part : parts)
      EXPECT_NE(what.find(part), std::string::npos) << "message '" << what << "' does not mention '" << part << "'";
    EXPECT_EQ(what.find('\n'), std::string::npos) << "message is not one line: " << what;
    return;
  } catch (const std::exception& e) {
    ADD_FAILURE() << "threw something other than InputError: " << e.what();
    return;
  }
  ADD_FAILURE() << "no InputError (expected '" << prefix << "')";
}

Parallelepiped skewed_box() {
  Eigen::Matrix3d axes;
  axes << 2.0, 0.3, 0.1,  //
      0.2, 1.5, -0.2,     //
      -0.1, 0.25, 1.2;
  return Parallelepiped(Eigen::Vector3d(-0.7, 0.4, 1.1), axes);
}

std::string quoted(const std::string& path) { return "'" + path + "'"; }

bool junit_valid(const std::string& xml_path, std::string* why) {
  const std::string dir = temp_folder("junit_valid");
  const std::string command = "xmllint --noout --schema " + quoted(std::string(FFD_SOURCE_DIR) + "/tests/data/junit.xsd") +
                              " " + quoted(xml_path) + " >" + quoted(dir + "/out") + " 2>&1";
  const int status = std::system(command.c_str());
  if (why) *why = read_file(dir + "/out");
  return WIFEXITED(status) && WEXITSTATUS(status) == 0;
}

std::string xpath(const std::string& xml_path, const std::string& expr) {
  const std::string dir = temp_folder("xpath");
  const std::string command = "xmllint --xpath " + quoted(expr) + " " + quoted(xml_path) + " >" + quoted(dir + "/out") + " 2>/dev/null";
  const int status = std::system(command.c_str());
  std::string out = WIFEXITED(status) && WEXITSTATUS(status) == 0 ? read_file(dir + "/out") : std::string();
  while (!out.empty() && out.back() == '\n') out.pop_back();
  return out;
}

std::set<std::string> files_in(const std::string& dir) {
  std::set<std::string> names;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) names.insert(entry.path().filename().string());
  return names;
}

nlohmann::json without_measurements(nlohmann::json j) {
  if (j.is_object()) {
    nlohmann::json out = nlohmann::json::object();
    for (auto it = j.begin(); it != j.end(); ++it) {
      const std::string& k = it.key();
      // frames_on_one_thread: how many frames the timing chose to run on one thread
      // (common/thread_choice.h), a measurement too; the frames' bytes do not depend on it.
      if (k == "ms" || (k.size() > 3 && k.compare(k.size() - 3, 3, "_ms") == 0) || k == "peak_memory_bytes" ||
          k == "frames_on_one_thread")
        continue;
      out[k] = without_measurements(it.value());
    }
    return out;
  }
  if (j.is_array())
    for (auto& e : j) e = without_measurements(e);
  return j;
}

std::vector<SoupFace> soup_faces(const PolygonSoup& soup) {
  const MeshElements& el = soup.elements;
  std::vector<SoupFace> faces;
  for (std::size_t e = 0; e < el.size(); ++e) {
    if (el.kinds[e] != ElementKind::Polygon) continue;
    SoupFace f;
    bool any_uv = false, any_vn = false;
    for (std::uint32_t c = el.begin(e); c < el.end(e); ++c) {
      f.vertices.push_back(el.corners[c]);
      f.uvs.push_back(el.uv(c));
      f.normals.push_back(el.normal(c));
      any_uv = any_uv || el.uv(c) >= 0;
      any_vn = any_vn || el.normal(c) >= 0;
    }
    if (!any_uv) f.uvs.clear();
    if (!any_vn) f.normals.clear();
    f.group = el.group(e);
    f.line = el.line(e);
    faces.push_back(std::move(f));
  }
  return faces;
}

void add_face(PolygonSoup& soup, const std::vector<std::uint32_t>& vertices, const std::vector<std::int32_t>& uvs,
              const std::vector<std::int32_t>& normals, std::int32_t group) {
  for (std::size_t c = 0; c < vertices.size(); ++c)
    soup.elements.add_corner(vertices[c], uvs.empty() ? -1 : uvs[c], normals.empty() ? -1 : normals[c]);
  soup.elements.close(ElementKind::Polygon, group);
}

// stderr holds exactly one line, "ffdtool: error: ...", mentioning every part.
void expect_one_error_line(const std::string& err, const std::vector<std::string>& parts) {
  EXPECT_EQ(err.rfind("ffdtool: error: ", 0), 0u) << "stderr: " << err;
  ASSERT_FALSE(err.empty());
  EXPECT_EQ(err.back(), '\n') << err;
  EXPECT_EQ(err.find('\n'), err.size() - 1) << "more than one line on stderr:\n" << err;
  for (const std::string& part : parts)
    EXPECT_NE(err.find(part), std::string::npos) << "stderr does not mention '" << part << "': " << err;
}

std::string cgal_meshes() { return fs::is_directory(FFD_CGAL_MESHES) ? std::string(FFD_CGAL_MESHES) : std::string(); }

std::string cgal_mesh(const std::string& name) {
  const std::string dir = cgal_meshes();
  return !dir.empty() && fs::exists(dir + "/" + name) ? dir + "/" + name : std::string();
}

std::string script(const std::vector<std::string>& steps) {
  std::string s = R"({"version": 1, "steps": [)";
  for (std::size_t i = 0; i < steps.size(); ++i) s += (i ? ",\n  " : "\n  ") + steps[i];
  return s + "]}";
}

std::string script_with(const std::string& steps) { return R"({"version": 1, "steps": [)" + steps + "]}"; }

int run_script(const std::string& dir, const std::string& name, const std::vector<std::string>& steps,
               std::string* err, const std::string& mesh) {
  write_file(dir + "/" + name + ".json", script(steps));
  return run_tool("run " + quoted(mesh.empty() ? data("bunny.obj") : mesh) + " " + quoted(dir + "/" + name + ".json") +
                      " -o " + quoted(dir + "/" + name + ".off") + " --stats " +
                      quoted(dir + "/" + name + ".stats.json") + " --quiet",
                  nullptr, err);
}

Eigen::Matrix3d central_jacobian(const Warp& warp, const Eigen::Vector3d& x, double h) {
  Eigen::Matrix3d fd;
  for (int a = 0; a < 3; ++a)
    fd.col(a) = (warp.apply(x + h * Eigen::Vector3d::Unit(a), nullptr) - warp.apply(x - h * Eigen::Vector3d::Unit(a), nullptr)) / (2 * h);
  return fd;
}

std::vector<std::size_t> all_ids(std::size_t n) {
  std::vector<std::size_t> ids(n);
  for (std::size_t i = 0; i < n; ++i) ids[i] = i;
  return ids;
}

void control_points(const Mesh& mesh, int stride, unsigned seed, std::vector<Eigen::Vector3d>& X,
                    std::vector<Eigen::Vector3d>& Y, double& diag) {
  const Eigen::Matrix3Xd p = mesh.positions();
  diag = (p.rowwise().maxCoeff() - p.rowwise().minCoeff()).norm();
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-0.03, 0.03);
  for (Eigen::Index v = 0; v < p.cols() && X.size() < 40; v += stride) {
    X.push_back(p.col(v));
    Y.push_back(X.back() + diag * Eigen::Vector3d(u(rng), u(rng), u(rng)));
  }
}

}  // namespace ffd::test
