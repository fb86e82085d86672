// The pieces gmsh_io.cpp (MSH 4.1, sections, result) and gmsh2_io.cpp (MSH 2.2 nodes and
// elements) share: a bounds-checked cursor over the file's bytes, Gmsh's element kinds,
// the node tag map and what the sections read so far. Internal to the MSH reader.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <string_view>
#include <unordered_map>
#include <utility>
#include <vector>

#include "mesh/volume_mesh.h"
#include "mesh/volume_patch.h"

namespace ffd::msh {

/// A Gmsh element type: its node count (0: Gmsh defines no such type), dimension, VTK
/// kind and corner order (VTK corner c is Gmsh node order[c]; null: the same order).
struct ElementKind {
  std::uint16_t nodes = 0;
  std::int8_t dimension = -1;
  std::uint8_t vtk = cell_type::kOtherCell;
  const std::uint8_t* order = nullptr;
};

/// The largest node count of a Gmsh element type (MSH_HEX_1000).
inline constexpr std::size_t kMaxElementNodes = 1000;

/// A cursor over the file's bytes. Text reads skip whitespace and take one token; binary
/// reads take fixed-size numbers in the file's byte order. Every read is bounds-checked;
/// errors are placed at the start of the last value read.
class Cursor {
public:
  Cursor(std::string_view text, const std::string& path) : text_(text), path_(path) {}

  std::size_t pos = 0;
  bool binary = false;      // the data sections are binary (headers and names stay text)
  bool swap = false;        // the file's byte order is not this machine's
  int size_bytes = 8;       // MSH 4.1 size_t width (data-size)

  std::string_view text() const { return text_; }
  const std::string& path() const { return path_; }
  std::size_t left() const { return text_.size() - pos; }
  std::size_t last() const { return last_; }

  // Text
  std::string_view token();
  std::uint64_t count(const char* what);
  std::int64_t integer(const char* what);
  double number(const char* what);
  void expect(std::string_view word);
  /// Moves past the rest of the line (blanks only) and its '\n': binary data follows.
  void end_line();

  // Binary (need: the file holds `bytes` more bytes, else "the file ends inside what")
  void need(std::uint64_t bytes, const char* what);
  std::int32_t int32(const char* what);
  std::uint64_t size_value(const char* what);
  double real(const char* what);
  std::int32_t load_int32(const char* at) const;
  std::uint64_t load_size(const char* at) const;
  double load_real(const char* at) const;

  // Either, as the data sections are written
  std::int64_t read_int(const char* what) { return binary ? int32(what) : integer(what); }
  std::uint64_t read_size(const char* what) { return binary ? size_value(what) : count(what); }
  double read_real(const char* what) { return binary ? real(what) : number(what); }
  /// Moves past a double the reader does not use (any bits in binary, any token in text).
  void skip_real(const char* what);

  /// Refuses a count of items of at least `bytes_each` bytes that the rest cannot hold.
  void fits(std::uint64_t count, std::uint64_t bytes_each, const char* what);
  /// "FILE:LINE" (text files) or "FILE: byte N" (binary files) of byte `at`.
  std::string where(std::size_t at) const;
  [[noreturn]] void fail(std::size_t at, const std::string& message) const;
  [[noreturn]] void fail(const std::string& message) const { fail(last_, message); }

private:
  std::string_view text_;
  const std::string& path_;
  std::size_t last_ = 0;
};

/// A token for a message: quoted, cut at 40 characters.
std::string quoted(std::string_view token);

/// Node tags to 0-based indices in file order: a vector over [min, max] when the tags are
/// dense, a hash map when they are sparse.
class NodeMap {
public:
  static constexpr std::uint32_t kMissing = 0xffffffffu;
  /// \throw InputError at `cursor`'s byte `at` on a tag 0 or a repeated tag.
  void build(const std::vector<std::uint64_t>& tags, const Cursor& cursor, std::size_t at);
  std::uint32_t find(std::uint64_t tag) const {
    if (!dense_.empty()) return tag >= min_ && tag - min_ < dense_.size() ? dense_[tag - min_] : kMissing;
    const auto it = sparse_.find(tag);
    return it == sparse_.end() ? kMissing : it->second;
  }

private:
  std::uint64_t min_ = 0;
  std::vector<std::uint32_t> dense_;
  std::unordered_map<std::uint64_t, std::uint32_t> sparse_;
};

/// A physical group: (dimension, tag).
using GroupKey = std::pair<int, std::int64_t>;

/// What the sections have read so far.
struct MshMesh {
  Eigen::Matrix3Xd points;
  std::vector<std::uint64_t> node_tags;     // file order
  std::vector<std::uint64_t> spans;         // text: node i's "x y z" is [spans[2i], spans[2i+1])
  std::vector<BinaryBlock> blocks;          // binary: where the coordinates are
  NodeMap nodes;
  VolumeCells cells;
  bool has_3d = false;                       // an element of dimension 3
  std::map<GroupKey, std::vector<std::uint64_t>> groups;
  std::map<GroupKey, std::string> names;
  std::map<GroupKey, std::vector<std::int64_t>> entity_groups;  // 4.1: (dim, entity) → physical tags
  bool has_entities = false;  // 4.1: entity_groups holds $Entities or $PartitionedEntities
  bool has_model_entities = false, has_partitions = false, has_nodes = false, has_elements = false;
  std::uint32_t element[kMaxElementNodes] = {};  // the element being read: node indices, Gmsh order

  /// Appends the element in `element` (kind's node count) as a cell.
  void add_element(const ElementKind& kind);
  /// Appends `count` cells of `kind` at once and returns their nodes (count × kind.nodes)
  /// for the caller to fill in Gmsh's order, then to_vtk_order.
  std::uint32_t* append_cells(const ElementKind& kind, std::uint64_t count);
  void to_vtk_order(const ElementKind& kind, std::uint32_t* cell_nodes, std::uint64_t count) const;
  /// The index of node `node_tag` of element `element_tag`. \throw InputError when no
  /// node has that tag.
  std::uint32_t node_index(std::uint64_t node_tag, std::uint64_t element_tag, const Cursor& cursor) const {
    const std::uint32_t index = nodes.find(node_tag);
    if (index == NodeMap::kMissing) unknown_node(std::to_string(node_tag), std::to_string(element_tag), cursor, cursor.last());
    return index;
  }
  /// \throw InputError at byte `at`: element `element_tag` names node `node_tag`, unknown.
  [[noreturn]] static void unknown_node(const std::string& node_tag, const std::string& element_tag, const Cursor& cursor,
                                        std::size_t at);
  /// Room for `count` nodes (the file has room for them: Cursor::fits first).
  void reserve_nodes(std::uint64_t count, bool text);
  /// The node map, once every node is read (`at`: the $Nodes section, for its errors).
  void finish_nodes(const Cursor& cursor, std::size_t at);
};

/// The kind of Gmsh element type `type`. \throw InputError at the cursor's last value on
/// a type Gmsh does not define or one without a fixed node count.
const ElementKind& element_kind(std::int64_t type, const Cursor& cursor);

/// MSH 2.2's $Nodes and $Elements, after the section's name.
void read_nodes_v2(Cursor& cursor, MshMesh& mesh);
void read_elements_v2(Cursor& cursor, MshMesh& mesh);

}  // namespace ffd::msh
