#include "script/script_values.h"

#include <cmath>
#include <filesystem>

#include "mesh/mesh_io.h"
#include "script/point_file.h"
#include "script/selection.h"

namespace ffd {
namespace {

using json = nlohmann::json;

Eigen::Vector3d vec3(const json& j) { return {j[0].get<double>(), j[1].get<double>(), j[2].get<double>()}; }

/// A file named in the script (the string j), relative to the script's folder; fails at
/// `place` when absent.
std::string script_file(const json& j, const ScriptPlace& place, const char* what) {
  std::string file = j.get<std::string>();
  if (!file.empty() && file[0] != '/' && !place.folder.empty()) file = place.folder + "/" + file;
  std::error_code ec;
  if (!std::filesystem::is_regular_file(file, ec)) place.fail(std::string("no such ") + what + " '" + file + "'");
  return file;
}

// One schema-checked selection part; `file` entries are read now.
SelectionPart read_part(const json& part, const ScriptPlace& place) {
  SelectionPart out;
  out.place = place.text();
  if (part.contains("indices")) {
    out.kind = SelectionPart::Kind::Indices;
    for (const json& entry : part["indices"]) {
      SelectionPart::Entry e;
      e.text = entry.dump();
      e.lattice = entry.is_array();
      if (e.lattice)
        e.ijk = {entry[0].get<int>(), entry[1].get<int>(), entry[2].get<int>()};
      else
        e.vertex = entry.get<long long>();
      out.indices.push_back(e);
    }
  } else if (part.contains("sphere")) {
    out.kind = SelectionPart::Kind::Sphere;
    out.center = vec3(part["sphere"]["center"]);
    out.radius = part["sphere"]["radius"].get<double>();
  } else if (part.contains("box")) {
    out.kind = SelectionPart::Kind::Box;
    out.min = vec3(part["box"]["min"]);
    out.max = vec3(part["box"]["max"]);
  } else if (part.contains("near")) {
    out.kind = SelectionPart::Kind::Near;
    out.center = vec3(part["near"]);
  } else if (part.contains("marker")) {
    out.kind = SelectionPart::Kind::Marker;
    out.marker = part["marker"].get<std::string>();
  } else {
    out.kind = SelectionPart::Kind::File;
    const std::string file = script_file(part["file"], place.at("/file"), "selection file");
    out.file = file;
    out.file_vertices = read_index_file(file);  // throws with the file's line on a malformed entry
  }
  return out;
}

}  // namespace

void read_value(const json& j, double& out, const ScriptPlace&) { out = j.get<double>(); }
void read_value(const json& j, int& out, const ScriptPlace&) { out = j.get<int>(); }
void read_value(const json& j, long long& out, const ScriptPlace&) { out = j.get<long long>(); }
void read_value(const json& j, bool& out, const ScriptPlace&) { out = j.get<bool>(); }
void read_value(const json& j, std::string& out, const ScriptPlace&) { out = j.get<std::string>(); }
void read_value(const json& j, Eigen::Vector3d& out, const ScriptPlace&) { out = vec3(j); }
void read_value(const json& j, Index3& out, const ScriptPlace&) {
  out = {j[0].get<int>(), j[1].get<int>(), j[2].get<int>()};
}

void read_value(const json& j, Transform& out, const ScriptPlace& place) {
  out = Transform{};
  if (j.contains("translate")) out.translate = vec3(j["translate"]);
  if (j.contains("scale")) {
    const json& s = j["scale"];
    out.scale = s.is_number() ? Eigen::Vector3d::Constant(s.get<double>()) : vec3(s);
  }
  if (j.contains("center")) out.center = vec3(j["center"]);
  if (j.contains("rotate")) {
    const Eigen::Vector3d axis = vec3(j["rotate"]["axis"]);
    if (!(axis.norm() > 0)) place.at("/rotate/axis").fail("the rotation axis is zero");
    const double radians = j["rotate"]["degrees"].get<double>() * M_PI / 180.0;
    out.rotation = Eigen::AngleAxisd(radians, axis.normalized()).toRotationMatrix();
  }
}

void read_value(const json& j, Selection& out, const ScriptPlace& place) {
  out = Selection{};
  out.place = place.text();
  if (j.is_array())
    for (std::size_t i = 0; i < j.size(); ++i) out.parts.push_back(read_part(j[i], place.at("/" + std::to_string(i))));
  else
    out.parts.push_back(read_part(j, place));
}

void read_value(const json& j, BoxSpec& out, const ScriptPlace& place) {
  out = BoxSpec{};
  if (j.contains("min")) {
    out.kind = BoxSpec::Kind::MinMax;
    out.min = vec3(j["min"]);
    out.max = vec3(j["max"]);
  } else if (j.contains("origin")) {
    out.kind = BoxSpec::Kind::OriginAxes;
    out.origin = vec3(j["origin"]);
    for (int a = 0; a < 3; ++a) out.axes.col(a) = vec3(j["axes"][a]);
  } else {
    out.kind = BoxSpec::Kind::Fit;
    out.fit = j["fit"] == "obb" ? BoxSpec::Fit::Obb : j["fit"] == "min_volume" ? BoxSpec::Fit::MinVolume : BoxSpec::Fit::Aabb;
    out.padding = j["padding"].get<double>();
    if (j.contains("select")) read_value(j["select"], out.select, place.at("/select"));
  }
}

json write_value(double v) { return v; }
json write_value(int v) { return v; }
json write_value(bool v) { return v; }
json write_value(const std::string& v) { return v; }
json write_value(const Eigen::Vector3d& v) { return json::array({v[0], v[1], v[2]}); }
json write_value(const Index3& v) { return json::array({v[0], v[1], v[2]}); }

json write_value(const BoxSpec& v) {
  switch (v.kind) {
    case BoxSpec::Kind::MinMax:
      return {{"min", write_value(v.min)}, {"max", write_value(v.max)}};
    case BoxSpec::Kind::OriginAxes: {
      json axes = json::array();
      for (int a = 0; a < 3; ++a) axes.push_back(write_value(Eigen::Vector3d(v.axes.col(a))));
      return {{"origin", write_value(v.origin)}, {"axes", axes}};
    }
    case BoxSpec::Kind::Fit:
      break;
  }
  const char* fit = v.fit == BoxSpec::Fit::Obb ? "obb" : v.fit == BoxSpec::Fit::MinVolume ? "min_volume" : "aabb";
  return {{"fit", fit}, {"padding", v.padding}};
}

std::string frame_path(const std::string& pattern, std::size_t i) {
  std::string out;
  for (std::size_t at = 0; at < pattern.size();) {
    if (pattern.compare(at, 3, "{i}") == 0) {
      out += std::to_string(i);
      at += 3;
    } else {
      out += pattern[at++];
    }
  }
  return out;
}

void read_value(const json& j, PointPositions& out, const ScriptPlace& place) {
  out.file = script_file(j, place, "file of positions");  // j: the file's name
  out.points = read_point_file(out.file);  // throws with the file's line on a line it cannot read
}

void read_value(const json& j, PointIndex& out, const ScriptPlace&) {
  out = PointIndex{};
  out.grid = j.is_array();
  if (out.grid)
    out.ijk = {j[0].get<int>(), j[1].get<int>(), j[2].get<int>()};
  else
    out.n = j.get<long long>();
}

void read_value(const json& j, PointSource& out, const ScriptPlace& place) {
  out = PointSource{};
  if (j.is_array()) {
    for (const json& p : j) out.points.push_back(vec3(p));
  } else if (j.contains("file")) {
    out.file = script_file(j["file"], place.at("/file"), "file of positions");
    out.points = read_point_file(out.file);
  } else {
    Selection select;
    read_value(j["select"], select, place.at("/select"));
    out.select = std::move(select);
  }
}

void read_value(const json& j, MeshSource& out, const ScriptPlace& place) {
  out = MeshSource{};
  out.file = script_file(j, place, "mesh file");
  const Mesh mesh = read_mesh(out.file);
  for (Eigen::Index v = 0; v < mesh.positions().cols(); ++v) out.points.push_back(mesh.positions().col(v));
  out.faces = mesh.faces();
}

}  // namespace ffd
