// The script grammar's typed values and their conversions from (schema-checked) JSON:
// numbers, vectors, lattice indices, transforms, selections and lattice boxes. Key tables
// (step_keys.h) call read_value for each key's member; write_value gives a typed value
// back as JSON, so the tests can tie every schema default to its struct's default.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "common/errors.h"
#include "script/transform.h"
#include "warp/deformer.h"

namespace ffd {

using Index3 = std::array<int, 3>;

/// Where a value of a script is: the script's path (for messages), its folder (selection
/// files are relative to it) and the value's JSON pointer.
struct ScriptPlace {
  std::string script;
  std::string folder;
  std::string pointer;  // "/steps/3/support"

  /// The place of a value inside this one ("/indices/2").
  ScriptPlace at(const std::string& relative) const { return {script, folder, pointer + relative}; }
  /// "script.json: /steps/3/support".
  std::string text() const { return script + ": " + (pointer.empty() ? "/" : pointer); }
  /// \throw InputError placed here.
  [[noreturn]] void fail(const std::string& message) const { throw InputError(At{text()}, message); }
};

/// One part of a selection (docs/script-reference.md, selection_part), read and checked at load time.
struct SelectionPart {
  enum class Kind { Indices, Sphere, Box, Near, File, Marker };
  /// An entry of an `indices` list: a mesh vertex, or a lattice index [i, j, k].
  struct Entry {
    bool lattice = false;
    long long vertex = 0;
    Index3 ijk{0, 0, 0};
    std::string text;  // as written, for messages ("[2, 3, 4]")
  };
  Kind kind = Kind::Indices;
  std::string place;   // "script.json: /steps/3/support/1", for messages
  std::vector<Entry> indices;
  Eigen::Vector3d center = Eigen::Vector3d::Zero();  // sphere; near's point
  double radius = 0;
  Eigen::Vector3d min = Eigen::Vector3d::Zero(), max = Eigen::Vector3d::Zero();
  std::string file;    // as resolved against the script's folder
  std::vector<std::uint32_t> file_vertices;
  std::string marker;  // a volume mesh's marker or physical group, by name
};

/// Mesh vertices or lattice points: the union of its parts.
struct Selection {
  std::string place;  // "script.json: /steps/3/support"
  std::vector<SelectionPart> parts;
};

/// A lattice's box as the script gives it: corners, a parallelepiped, or a fit to the
/// current mesh (or a selection of it) with padding.
struct BoxSpec {
  enum class Kind { MinMax, OriginAxes, Fit };
  enum class Fit { Aabb, Obb, MinVolume };  // Obb: along the principal components
  Kind kind = Kind::Fit;
  Eigen::Vector3d min = Eigen::Vector3d::Zero(), max = Eigen::Vector3d::Zero();
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  Eigen::Matrix3d axes = Eigen::Matrix3d::Identity();
  Fit fit = Fit::Aabb;
  /// Added on every side, as a fraction of the fitted box's largest extent.
  double padding = 0.05;
  std::optional<Selection> select;
};

/// Positions of every point of a deformer's level, from a file (the move op's
/// positions/file), read with the script (point_file.h).
struct PointPositions {
  std::string file;  // as resolved against the script's folder
  std::vector<Eigen::Vector3d> points;
};

/// Control points as a script gives them (the grammar's `points`): a list of positions, a
/// file of positions (read with the script), or a selection of mesh vertices, whose
/// current positions the step takes when it runs.
struct PointSource {
  std::vector<Eigen::Vector3d> points;  // the list, or the file's points
  std::string file;                     // as resolved against the script's folder, or ""
  std::optional<Selection> select;
};

/// A mesh a step reads as its input, such as a cage (the cage op's `cage`), read with the
/// script: its vertices and its polygons.
struct MeshSource {
  std::string file;  // as resolved against the script's folder
  std::vector<Eigen::Vector3d> points;
  std::vector<std::vector<std::uint32_t>> faces;
};

void read_value(const nlohmann::json& j, double& out, const ScriptPlace& place);
void read_value(const nlohmann::json& j, int& out, const ScriptPlace& place);
void read_value(const nlohmann::json& j, long long& out, const ScriptPlace& place);
void read_value(const nlohmann::json& j, bool& out, const ScriptPlace& place);
void read_value(const nlohmann::json& j, std::string& out, const ScriptPlace& place);
void read_value(const nlohmann::json& j, Eigen::Vector3d& out, const ScriptPlace& place);
void read_value(const nlohmann::json& j, Index3& out, const ScriptPlace& place);
/// [i, j, k], or a plain integer n (the grammar's `point_index`).
void read_value(const nlohmann::json& j, PointIndex& out, const ScriptPlace& place);
/// \throw InputError as the selection or the file of positions does.
void read_value(const nlohmann::json& j, PointSource& out, const ScriptPlace& place);
/// \throw InputError at `place` for a missing file, as the mesh readers do for one they
/// cannot read.
void read_value(const nlohmann::json& j, MeshSource& out, const ScriptPlace& place);
/// \throw InputError at "/rotate/axis" when the rotation axis is zero.
void read_value(const nlohmann::json& j, Transform& out, const ScriptPlace& place);
/// Reads selection files now. \throw InputError for a missing file (at "/file") or a
/// malformed line (naming the file's line).
void read_value(const nlohmann::json& j, Selection& out, const ScriptPlace& place);
void read_value(const nlohmann::json& j, BoxSpec& out, const ScriptPlace& place);
/// Reads the file j names now. \throw InputError for a missing file (placed at `place`) or
/// a line it cannot read (naming the file's line).
void read_value(const nlohmann::json& j, PointPositions& out, const ScriptPlace& place);

template <class T>
void read_value(const nlohmann::json& j, std::optional<T>& out, const ScriptPlace& place) {
  T value{};
  read_value(j, value, place);
  out = std::move(value);
}

template <class T>
void read_value(const nlohmann::json& j, std::vector<T>& out, const ScriptPlace& place) {
  out.clear();
  for (std::size_t i = 0; i < j.size(); ++i) {
    T value{};
    read_value(j[i], value, place.at("/" + std::to_string(i)));
    out.push_back(std::move(value));
  }
}

nlohmann::json write_value(double v);
nlohmann::json write_value(int v);
nlohmann::json write_value(bool v);
nlohmann::json write_value(const std::string& v);
nlohmann::json write_value(const Eigen::Vector3d& v);
nlohmann::json write_value(const Index3& v);
/// The box as the script would give it (a selection is not written back).
nlohmann::json write_value(const BoxSpec& v);

/// A transform step's save pattern for frame i: each "{i}" replaced by i.
std::string frame_path(const std::string& pattern, std::size_t i);

}  // namespace ffd
