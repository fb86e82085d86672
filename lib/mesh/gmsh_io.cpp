// The MSH reader's sections and result, and MSH 4.1's $Entities, $Nodes and $Elements
// (MSH 2.2's are in gmsh2_io.cpp). Layouts: Gmsh's manual, "MSH file format".
#include "mesh/gmsh_io.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <memory>

#include "common/errors.h"
#include "mesh/gmsh_reader.h"
#include "mesh/volume_patch.h"

namespace ffd {
namespace {

using msh::Cursor;
using msh::ElementKind;
using msh::GroupKey;
using msh::MshMesh;

struct Format {
  std::string version;  // "4.1" or "2.2"
  bool binary = false;
};

// $MeshFormat: "version file-type data-size", and for binary files the int 1 that gives
// the byte order.
Format read_format(Cursor& cursor) {
  cursor.expect("$MeshFormat");
  Format format;
  format.version = std::string(cursor.token());
  if (format.version != "4.1" && format.version != "2.2")
    cursor.fail("MSH version " + msh::quoted(format.version) + " is not read (versions 4.1 and 2.2 are)");
  const std::uint64_t type = cursor.count("the file type (0 ASCII, 1 binary)");
  if (type > 1) cursor.fail("the file type must be 0 (ASCII) or 1 (binary), found " + std::to_string(type));
  const std::uint64_t size = cursor.count("the data size");
  const bool v4 = format.version == "4.1";
  if (size != 8 && !(v4 && size == 4))
    cursor.fail("data size " + std::to_string(size) + " is not read (" + (v4 ? "4 or 8" : "8") + " is)");
  cursor.size_bytes = static_cast<int>(size);
  format.binary = type == 1;
  if (format.binary) {
    cursor.end_line();
    cursor.need(4, "the binary byte-order marker");
    std::int32_t one;
    std::memcpy(&one, cursor.text().data() + cursor.pos, 4);
    if (one != 1 && one != 0x01000000) cursor.fail(cursor.pos, "the binary byte-order marker is not the int 1");
    cursor.swap = one != 1;
    cursor.pos += 4;
  }
  cursor.expect("$EndMeshFormat");
  return format;
}

// $PhysicalNames (text in every file): "dimension tag "name"" per line.
void read_physical_names(Cursor& cursor, MshMesh& mesh) {
  const bool binary = cursor.binary;
  cursor.binary = false;
  const std::uint64_t count = cursor.count("the number of physical names");
  cursor.fits(count, 6, "physical names");
  const std::string_view text = cursor.text();
  for (std::uint64_t i = 0; i < count; ++i) {
    const std::int64_t dimension = cursor.integer("a physical group's dimension");
    if (dimension < 0 || dimension > 3) cursor.fail("a physical group's dimension must be 0 to 3");
    const std::int64_t tag = cursor.integer("a physical group's tag");
    std::size_t end = text.find('\n', cursor.pos);
    if (end == std::string_view::npos) end = text.size();
    std::string_view name = text.substr(cursor.pos, end - cursor.pos);
    while (!name.empty() && (name.front() == ' ' || name.front() == '\t')) name.remove_prefix(1);
    while (!name.empty() && (name.back() == ' ' || name.back() == '\t' || name.back() == '\r')) name.remove_suffix(1);
    if (name.size() >= 2 && name.front() == '"' && name.back() == '"') name = name.substr(1, name.size() - 2);
    if (name.empty()) cursor.fail("physical group " + std::to_string(tag) + " has no name");
    mesh.names[{static_cast<int>(dimension), tag}] = std::string(name);
    cursor.pos = end;
  }
  cursor.expect("$EndPhysicalNames");
  cursor.binary = binary;
}

// A count of int tags, then the tags (4.1 $Entities, $PartitionedEntities).
std::vector<std::int64_t> read_tag_list(Cursor& cursor, const char* what) {
  const std::uint64_t count = cursor.read_size(what);
  cursor.fits(count, cursor.binary ? 4 : 2, what);
  std::vector<std::int64_t> tags(static_cast<std::size_t>(count));
  for (std::int64_t& tag : tags) tag = cursor.read_int(what);
  return tags;
}

// One entity of $Entities or $PartitionedEntities: its tag, for a partition's entity its
// parent and partitions, its bounding box, its physical tags (kept) and, above points,
// its bounding entities.
void read_entity(Cursor& cursor, MshMesh& mesh, int dimension, bool partitioned) {
  const std::int64_t tag = cursor.read_int("an entity's tag");
  if (partitioned) {
    cursor.read_int("an entity's parent dimension");
    cursor.read_int("an entity's parent tag");
    read_tag_list(cursor, "partitions");
  }
  for (int k = 0; k < (dimension ? 6 : 3); ++k) cursor.skip_real("an entity's bounding box");
  std::vector<std::int64_t> physical = read_tag_list(cursor, "physical tags");
  std::sort(physical.begin(), physical.end());  // a tag listed twice is one group
  physical.erase(std::unique(physical.begin(), physical.end()), physical.end());
  mesh.entity_groups[{dimension, tag}] = std::move(physical);
  if (dimension) read_tag_list(cursor, "bounding entities");
}

// The entity counts by dimension, then the entities (4.1 $Entities, $PartitionedEntities).
void read_entity_list(Cursor& cursor, MshMesh& mesh, bool partitioned) {
  std::uint64_t counts[4];
  for (std::uint64_t& count : counts) count = cursor.read_size("the number of entities");
  for (int dimension = 0; dimension < 4; ++dimension) {
    cursor.fits(counts[dimension], cursor.binary ? 4 + 24 + cursor.size_bytes : 10, "entities");
    for (std::uint64_t e = 0; e < counts[dimension]; ++e) read_entity(cursor, mesh, dimension, partitioned);
  }
  mesh.has_entities = true;
}

void read_entities(Cursor& cursor, MshMesh& mesh) {
  if (cursor.binary) cursor.end_line();
  read_entity_list(cursor, mesh, false);
  cursor.expect("$EndEntities");
}

// $PartitionedEntities: the partition count, the ghost entities (skipped), then the
// partitions' entities, whose physical groups the elements of a partitioned mesh use.
void read_partitioned_entities(Cursor& cursor, MshMesh& mesh) {
  if (cursor.binary) cursor.end_line();
  cursor.read_size("the number of partitions");
  const std::uint64_t ghosts = cursor.read_size("the number of ghost entities");
  cursor.fits(ghosts, cursor.binary ? 8 : 4, "ghost entities");
  for (std::uint64_t g = 0; g < 2 * ghosts; ++g) cursor.read_int("a ghost entity");
  read_entity_list(cursor, mesh, true);
  cursor.expect("$EndPartitionedEntities");
}

// ---- 4.1 $Nodes ----

// A block's coordinates in text: "x y z" and the parametric ones (kept as they are).
void read_node_coordinates_text(Cursor& cursor, MshMesh& mesh, std::uint64_t first, std::uint64_t count, int extra) {
  for (std::uint64_t j = 0; j < count; ++j) {
    const Eigen::Index i = static_cast<Eigen::Index>(first + j);
    for (int k = 0; k < 3; ++k) {
      mesh.points(k, i) = cursor.number("a coordinate");
      if (k == 0) mesh.spans.push_back(cursor.last());
    }
    mesh.spans.push_back(cursor.pos);
    for (int k = 0; k < extra; ++k) cursor.number("a parametric coordinate");
  }
}

// A block's tags and coordinates in binary, recorded as a BinaryBlock.
void read_node_block_binary(Cursor& cursor, MshMesh& mesh, std::uint64_t first, std::uint64_t count, int extra) {
  const std::uint64_t stride = 8 * static_cast<std::uint64_t>(3 + extra);
  cursor.fits(count, static_cast<std::uint64_t>(cursor.size_bytes) + stride, "nodes in the block");
  const char* at = cursor.text().data() + cursor.pos;
  for (std::uint64_t j = 0; j < count; ++j) mesh.node_tags.push_back(cursor.load_size(at + j * cursor.size_bytes));
  cursor.pos += count * cursor.size_bytes;
  mesh.blocks.push_back({first, count, cursor.pos, stride});
  at = cursor.text().data() + cursor.pos;
  for (std::uint64_t j = 0; j < count; ++j)
    for (int k = 0; k < 3; ++k) {
      const double x = cursor.load_real(at + j * stride + 8 * k);
      if (!std::isfinite(x)) cursor.fail(cursor.pos + j * stride, "node " + std::to_string(first + j) +
                                                                      " has a coordinate that is not finite");
      mesh.points(k, static_cast<Eigen::Index>(first + j)) = x;
    }
  cursor.pos += count * stride;
}

// One entity block of nodes: "dim entity parametric count", the tags, the coordinates.
void read_node_block(Cursor& cursor, MshMesh& mesh, std::uint64_t first, std::uint64_t total) {
  const std::int64_t dimension = cursor.read_int("a node block's entity dimension");
  if (dimension < 0 || dimension > 3) cursor.fail("a node block's entity dimension must be 0 to 3");
  cursor.read_int("a node block's entity tag");
  const std::int64_t parametric = cursor.read_int("a node block's parametric flag");
  if (parametric != 0 && parametric != 1) cursor.fail("a node block's parametric flag must be 0 or 1");
  const std::uint64_t count = cursor.read_size("a node block's node count");
  if (count > total - first)
    cursor.fail("the node blocks hold more than the " + std::to_string(total) + " nodes $Nodes promises");
  const int extra = parametric ? static_cast<int>(dimension) : 0;
  if (cursor.binary) return read_node_block_binary(cursor, mesh, first, count, extra);
  cursor.fits(count, 2 * (4 + extra), "nodes in the block");
  for (std::uint64_t j = 0; j < count; ++j) mesh.node_tags.push_back(cursor.count("a node tag"));
  read_node_coordinates_text(cursor, mesh, first, count, extra);
}

void read_nodes_v4(Cursor& cursor, MshMesh& mesh) {
  const std::size_t section = cursor.last();
  if (cursor.binary) cursor.end_line();
  const std::uint64_t blocks = cursor.read_size("the number of node blocks");
  const std::uint64_t total = cursor.read_size("the number of nodes");
  cursor.read_size("the smallest node tag");
  cursor.read_size("the largest node tag");
  const std::size_t header = cursor.last();
  cursor.fits(blocks, cursor.binary ? 12 + cursor.size_bytes : 8, "node blocks");
  cursor.fits(total, cursor.binary ? cursor.size_bytes + 24 : 8, "nodes");
  mesh.reserve_nodes(total, !cursor.binary);
  std::uint64_t read = 0;
  for (std::uint64_t b = 0; b < blocks; ++b) {
    const std::size_t before = mesh.node_tags.size();
    read_node_block(cursor, mesh, read, total);
    read += mesh.node_tags.size() - before;
  }
  if (read != total)
    cursor.fail(header, "$Nodes promises " + std::to_string(total) + " nodes, its blocks hold " + std::to_string(read));
  cursor.expect("$EndNodes");
  mesh.finish_nodes(cursor, section);
}

// ---- 4.1 $Elements ----

// The physical tags of an element block's entity (none without $Entities).
const std::vector<std::int64_t>* entity_groups(const Cursor& cursor, const MshMesh& mesh, GroupKey entity) {
  if (!mesh.has_entities) return nullptr;
  const auto it = mesh.entity_groups.find(entity);
  if (it != mesh.entity_groups.end()) return &it->second;
  cursor.fail("an element block names entity " + std::to_string(entity.second) + " of dimension " +
              std::to_string(entity.first) + ", which $Entities does not list");
}

// Elements [first, first + count) join the groups `tags` of dimension `dimension`.
void add_block_to_groups(MshMesh& mesh, const std::vector<std::int64_t>* tags, int dimension, std::uint64_t first,
                         std::uint64_t count) {
  if (!tags) return;
  for (const std::int64_t tag : *tags) {
    std::vector<std::uint64_t>& cells = mesh.groups[{dimension, tag}];
    cells.reserve(cells.size() + count);
    for (std::uint64_t c = first; c < first + count; ++c) cells.push_back(c);
  }
}

void read_element_block_text(Cursor& cursor, MshMesh& mesh, const ElementKind& kind, std::uint64_t count) {
  std::uint32_t* const nodes = mesh.append_cells(kind, count);
  std::uint32_t* slot = nodes;
  for (std::uint64_t e = 0; e < count; ++e) {
    const std::uint64_t tag = cursor.count("an element tag");
    for (std::size_t k = 0; k < kind.nodes; ++k) *slot++ = mesh.node_index(cursor.count("a node tag"), tag, cursor);
  }
  mesh.to_vtk_order(kind, nodes, count);
}

void read_element_block_binary(Cursor& cursor, MshMesh& mesh, const ElementKind& kind, std::uint64_t count) {
  const std::size_t size = static_cast<std::size_t>(cursor.size_bytes);
  const std::size_t record = size * (1 + kind.nodes);
  std::uint32_t* const nodes = mesh.append_cells(kind, count);
  std::uint32_t* slot = nodes;
  for (std::uint64_t e = 0; e < count; ++e, cursor.pos += record) {
    const char* at = cursor.text().data() + cursor.pos;
    for (std::size_t k = 0; k < kind.nodes; ++k) {
      const std::uint64_t node = cursor.load_size(at + size * (1 + k));
      *slot = mesh.nodes.find(node);
      if (*slot++ == msh::NodeMap::kMissing)
        MshMesh::unknown_node(std::to_string(node), std::to_string(cursor.load_size(at)), cursor, cursor.pos);
    }
  }
  mesh.to_vtk_order(kind, nodes, count);
}

// One entity block of elements: "dim entity type count", then per element its tag and nodes.
void read_element_block(Cursor& cursor, MshMesh& mesh, std::uint64_t total) {
  const std::int64_t dimension = cursor.read_int("an element block's entity dimension");
  if (dimension < 0 || dimension > 3) cursor.fail("an element block's entity dimension must be 0 to 3");
  const std::int64_t entity = cursor.read_int("an element block's entity tag");
  const std::vector<std::int64_t>* groups = entity_groups(cursor, mesh, {static_cast<int>(dimension), entity});
  const ElementKind& kind = msh::element_kind(cursor.read_int("an element type"), cursor);
  const std::uint64_t count = cursor.read_size("an element block's element count");
  const std::uint64_t first = mesh.cells.size();
  if (count > total - first)
    cursor.fail("the element blocks hold more than the " + std::to_string(total) + " elements $Elements promises");
  const std::uint64_t record = (cursor.binary ? cursor.size_bytes : 2) * (1 + static_cast<std::uint64_t>(kind.nodes));
  cursor.fits(count, record, "elements in the block");
  if (cursor.binary)
    read_element_block_binary(cursor, mesh, kind, count);
  else
    read_element_block_text(cursor, mesh, kind, count);
  add_block_to_groups(mesh, groups, static_cast<int>(dimension), first, count);
}

void read_elements_v4(Cursor& cursor, MshMesh& mesh) {
  if (cursor.binary) cursor.end_line();
  const std::uint64_t blocks = cursor.read_size("the number of element blocks");
  const std::uint64_t total = cursor.read_size("the number of elements");
  cursor.read_size("the smallest element tag");
  cursor.read_size("the largest element tag");
  const std::size_t header = cursor.last();
  cursor.fits(blocks, cursor.binary ? 12 + cursor.size_bytes : 8, "element blocks");
  cursor.fits(total, cursor.binary ? 2 * cursor.size_bytes : 4, "elements");
  mesh.cells.type.reserve(total);
  mesh.cells.offset.reserve(total + 1);
  for (std::uint64_t b = 0; b < blocks; ++b) read_element_block(cursor, mesh, total);
  if (mesh.cells.size() != total)
    cursor.fail(header, "$Elements promises " + std::to_string(total) + " elements, its blocks hold " +
                            std::to_string(mesh.cells.size()));
  cursor.expect("$EndElements");
}

// ---- Sections ----

// Moves past a section this reader carries without reading: to its "$End<name>" at the
// start of a line.
void skip_section(Cursor& cursor, std::string_view name) {
  const std::size_t section = cursor.last();
  const std::string end = "$End" + std::string(name);
  const std::string_view text = cursor.text();
  for (std::size_t at = text.find(end, cursor.pos); at != std::string_view::npos; at = text.find(end, at + 1)) {
    const std::size_t after = at + end.size();
    const bool alone = at > 0 && text[at - 1] == '\n' && (after == text.size() || std::isspace(static_cast<unsigned char>(text[after])));
    if (!alone) continue;
    cursor.pos = after;
    return;
  }
  cursor.fail(section, "section $" + std::string(name) + " has no " + end);
}

void read_section(Cursor& cursor, const Format& format, std::string_view name, MshMesh& mesh) {
  const bool v4 = format.version == "4.1";
  const auto once = [&](bool& seen) {
    if (seen) cursor.fail("a second $" + std::string(name) + " section");
    seen = true;
  };
  if (name == "PhysicalNames") return read_physical_names(cursor, mesh);
  if ((name == "Entities" || name == "PartitionedEntities") && v4) {
    if (mesh.has_elements) cursor.fail("$" + std::string(name) + " comes after $Elements");
    if (name == "Entities") {
      once(mesh.has_model_entities);
      return read_entities(cursor, mesh);
    }
    once(mesh.has_partitions);
    return read_partitioned_entities(cursor, mesh);
  }
  if (name == "Nodes") {
    if (mesh.has_nodes) cursor.fail("a second $Nodes section");
    return v4 ? read_nodes_v4(cursor, mesh) : msh::read_nodes_v2(cursor, mesh);
  }
  if (name == "Elements") {
    if (!mesh.has_nodes) cursor.fail("$Elements comes before $Nodes");
    once(mesh.has_elements);
    return v4 ? read_elements_v4(cursor, mesh) : msh::read_elements_v2(cursor, mesh);
  }
  if (name.substr(0, 3) == "End") cursor.fail(msh::quoted(std::string("$") + std::string(name)) + " closes no section");
  skip_section(cursor, name);
}

// ---- Result ----

// One marker per physical group, by (dimension, tag): the named ones and those elements use.
std::vector<VolumeMarker> make_markers(MshMesh& mesh) {
  for (const auto& [key, name] : mesh.names) mesh.groups[key];
  std::vector<VolumeMarker> markers;
  markers.reserve(mesh.groups.size());
  for (auto& [key, cells] : mesh.groups) {
    const auto name = mesh.names.find(key);
    markers.push_back({name != mesh.names.end() ? name->second : std::to_string(key.second), key.first,
                       std::move(cells)});
  }
  return markers;
}

// For a planar mesh only x and y are rewritten: each text span ends at its y.
void spans_to_y(std::string_view text, std::vector<std::uint64_t>& spans) {
  for (std::size_t i = 1; i < spans.size(); i += 2) {
    std::uint64_t end = spans[i];
    while (end > spans[i - 1] && !std::isspace(static_cast<unsigned char>(text[end - 1]))) --end;  // z
    while (end > spans[i - 1] && std::isspace(static_cast<unsigned char>(text[end - 1]))) --end;
    spans[i] = end;
  }
}

VolumeRead make_result(SharedBytes bytes, const Format& format, Cursor& cursor, MshMesh& mesh) {
  if (!mesh.has_nodes) cursor.fail(cursor.text().size(), "the file has no $Nodes section");
  if (!mesh.has_elements) cursor.fail(cursor.text().size(), "the file has no $Elements section");
  VolumeRead read;
  read.points = std::move(mesh.points);
  VolumeSource& source = read.source;
  source.format = VolumeFormat::Msh;
  source.version = format.version;
  source.encoding = format.binary ? "binary" : "ascii";
  const bool planar = !mesh.has_3d && (read.points.cols() == 0 || (read.points.row(2).array() == 0).all());
  source.dimension = planar ? 2 : 3;
  source.cells = std::move(mesh.cells);
  source.markers = make_markers(mesh);
  const BinaryScalar scalar{true, cursor.swap != (__BYTE_ORDER__ == __ORDER_BIG_ENDIAN__)};
  if (format.binary) {
    source.file = std::make_shared<BinaryPoints>(std::move(bytes), std::move(mesh.blocks), scalar, source.dimension);
  } else {
    if (planar) spans_to_y(*bytes, mesh.spans);
    source.file = std::make_shared<TextPoints>(std::move(bytes), std::move(mesh.spans), source.dimension, read.points);
  }
  return read;
}

}  // namespace

VolumeRead read_msh(SharedBytes bytes, const std::string& path) {
  Cursor cursor(*bytes, path);
  const Format format = read_format(cursor);
  cursor.binary = format.binary;
  MshMesh mesh;
  for (std::string_view name = cursor.token(); !name.empty(); name = cursor.token()) {
    if (name[0] != '$' || name.size() == 1) cursor.fail("expected a section such as $Nodes, found " + msh::quoted(name));
    read_section(cursor, format, name.substr(1), mesh);
  }
  return make_result(std::move(bytes), format, cursor, mesh);
}

}  // namespace ffd
