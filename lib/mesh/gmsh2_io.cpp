// MSH 2.2's $Nodes and $Elements (gmsh_io.cpp reads the rest). ASCII: "tag x y z" per
// node, "tag type ntags tags... nodes..." per element. Binary: after the text count,
// nodes are records (int tag, 3 doubles) and elements come in runs of one type, each
// headed by three ints (type, elements in the run, tags per element), then per element
// ints: tag, tags, nodes. An element's physical group is its first tag (0: none).
#include <cmath>

#include "common/errors.h"
#include "mesh/gmsh_reader.h"

namespace ffd::msh {
namespace {

constexpr std::uint64_t kNodeRecord = 4 + 3 * 8;

// Appends elements to their physical groups, remembering the last group used: runs of
// elements of one group are the common case.
class GroupAdder {
public:
  explicit GroupAdder(MshMesh& mesh) : mesh_(mesh) {}
  void add(int dimension, std::int64_t physical, std::uint64_t element) {
    if (physical == 0) return;
    const GroupKey key{dimension, physical};
    if (!cells_ || key != key_) {
      key_ = key;
      cells_ = &mesh_.groups[key];
    }
    cells_->push_back(element);
  }

private:
  MshMesh& mesh_;
  GroupKey key_;
  std::vector<std::uint64_t>* cells_ = nullptr;
};

void read_node_records_binary(Cursor& cursor, MshMesh& mesh, std::uint64_t count) {
  cursor.end_line();
  cursor.fits(count, kNodeRecord, "nodes");
  mesh.reserve_nodes(count, false);
  const char* at = cursor.text().data() + cursor.pos;
  for (std::uint64_t i = 0; i < count; ++i, at += kNodeRecord) {
    const std::int32_t tag = cursor.load_int32(at);
    if (tag <= 0) cursor.fail(cursor.pos + i * kNodeRecord, "node tag " + std::to_string(tag) + " (tags start at 1)");
    mesh.node_tags.push_back(static_cast<std::uint64_t>(tag));
    for (int k = 0; k < 3; ++k) {
      const double x = cursor.load_real(at + 4 + 8 * k);
      if (!std::isfinite(x))
        cursor.fail(cursor.pos + i * kNodeRecord, "node " + std::to_string(tag) + " has a coordinate that is not finite");
      mesh.points(k, static_cast<Eigen::Index>(i)) = x;
    }
  }
  mesh.blocks.push_back({0, count, cursor.pos + 4, kNodeRecord});
  cursor.pos += count * kNodeRecord;
}

void read_node_lines(Cursor& cursor, MshMesh& mesh, std::uint64_t count) {
  cursor.fits(count, 8, "nodes");
  mesh.reserve_nodes(count, true);
  for (std::uint64_t i = 0; i < count; ++i) {
    mesh.node_tags.push_back(cursor.count("a node tag"));
    for (int k = 0; k < 3; ++k) {
      mesh.points(k, static_cast<Eigen::Index>(i)) = cursor.number("a coordinate");
      if (k == 0) mesh.spans.push_back(cursor.last());
    }
    mesh.spans.push_back(cursor.pos);
  }
}

// One element line: "tag type ntags tags... nodes...".
void read_element_line(Cursor& cursor, MshMesh& mesh, GroupAdder& groups) {
  const std::uint64_t tag = cursor.count("an element tag");
  const ElementKind& kind = element_kind(cursor.integer("an element type"), cursor);
  const std::uint64_t tags = cursor.count("the number of tags");
  cursor.fits(tags, 2, "tags");
  std::int64_t physical = 0;
  for (std::uint64_t t = 0; t < tags; ++t) {
    const std::int64_t value = cursor.integer("a tag");
    if (t == 0) physical = value;
  }
  for (std::size_t k = 0; k < kind.nodes; ++k) mesh.element[k] = mesh.node_index(cursor.count("a node tag"), tag, cursor);
  groups.add(kind.dimension, physical, mesh.cells.size());
  mesh.add_element(kind);
}

// One binary run's elements: `count` records of `tags` tags each.
void read_element_run(Cursor& cursor, MshMesh& mesh, const ElementKind& kind, std::uint64_t count,
                      std::uint64_t tags, GroupAdder& groups) {
  const std::uint64_t record = 4 * (1 + tags + kind.nodes);
  cursor.fits(count, record, "elements in the run");
  std::uint32_t* const nodes = mesh.append_cells(kind, count);
  std::uint32_t* slot = nodes;
  const std::uint64_t first = mesh.cells.size() - count;
  for (std::uint64_t e = 0; e < count; ++e, cursor.pos += record) {
    const char* at = cursor.text().data() + cursor.pos;
    for (std::size_t k = 0; k < kind.nodes; ++k) {
      const std::int32_t node = cursor.load_int32(at + 4 * (1 + tags + k));
      *slot = node > 0 ? mesh.nodes.find(static_cast<std::uint64_t>(node)) : NodeMap::kMissing;
      if (*slot++ == NodeMap::kMissing)
        MshMesh::unknown_node(std::to_string(node), std::to_string(cursor.load_int32(at)), cursor, cursor.pos);
    }
    groups.add(kind.dimension, tags ? cursor.load_int32(at + 4) : 0, first + e);
  }
  mesh.to_vtk_order(kind, nodes, count);
}

void read_element_runs(Cursor& cursor, MshMesh& mesh, std::uint64_t count, GroupAdder& groups) {
  cursor.end_line();
  while (mesh.cells.size() < count) {
    const ElementKind& kind = element_kind(cursor.int32("an element run's type"), cursor);
    const std::int32_t run = cursor.int32("an element run's element count");
    if (run <= 0 || static_cast<std::uint64_t>(run) > count - mesh.cells.size())
      cursor.fail("a run of " + std::to_string(run) + " elements, where " +
                  std::to_string(count - mesh.cells.size()) + " of the $Elements count remain");
    const std::int32_t tags = cursor.int32("an element run's tag count");
    if (tags < 0) cursor.fail("a run's tag count is negative");
    read_element_run(cursor, mesh, kind, static_cast<std::uint64_t>(run), static_cast<std::uint64_t>(tags), groups);
  }
}

}  // namespace

void read_nodes_v2(Cursor& cursor, MshMesh& mesh) {
  const std::size_t section = cursor.last();
  const std::uint64_t count = cursor.count("the number of nodes");
  if (cursor.binary)
    read_node_records_binary(cursor, mesh, count);
  else
    read_node_lines(cursor, mesh, count);
  cursor.expect("$EndNodes");
  mesh.finish_nodes(cursor, section);
}

void read_elements_v2(Cursor& cursor, MshMesh& mesh) {
  const std::uint64_t count = cursor.count("the number of elements");
  cursor.fits(count, 8, "elements");
  mesh.cells.type.reserve(count);
  mesh.cells.offset.reserve(count + 1);
  GroupAdder groups(mesh);
  if (cursor.binary) {
    read_element_runs(cursor, mesh, count, groups);
  } else {
    for (std::uint64_t e = 0; e < count; ++e) read_element_line(cursor, mesh, groups);
  }
  cursor.expect("$EndElements");
}

}  // namespace ffd::msh
