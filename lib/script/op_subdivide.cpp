// The subdivide op: Ono et al.'s local subdivision (section 2.2, Figure 3) of chosen cells
// of an octree level, as a new level.
#include "common/numbers.h"
#include "multires/octree_lattice.h"
#include "script/op.h"
#include "script/selection.h"

namespace ffd {
namespace {

struct SubdivideStep final : Step {
  std::string lattice;
  std::optional<int> level;
  Selection cells;

  void check(ScriptChecks& checks) const override;
  void run(Scene& scene, StepContext& ctx) const override;
};

KeyTable<SubdivideStep> subdivide_keys() {
  using S = SubdivideStep;
  return {{key<S>("/lattice", schema_text(), nullptr, "Name of an octree lattice created earlier.",
                  [](auto& s) -> auto& { return s.lattice; })
               .required()
               .about("lattice"),
           key<S>("/level", schema_integer(0), nullptr,
                  "The octree level whose cells are subdivided (default: the finest). The result is a new level, "
                  "numbered after the existing ones (the stats say which), made from this level as it is now.",
                  [](auto& s) -> auto& { return s.level; }),
           key<S>("/cells", schema_ref("selection"), nullptr,
                  "The cells: [i, j, k] cell indices of the level, or by position (near: the cell nearest the "
                  "point; sphere and box: the cells whose centroids lie inside).",
                  [](auto& s) -> auto& { return s.cells; })
               .required()}};
}

void SubdivideStep::check(ScriptChecks& checks) const {
  checks.deformer_of(lattice, pointer + "/lattice");
  DeformerShape& shape = checks.deformers.at(lattice);
  if (shape.subdividable < 0) checks.fail(pointer + "/lattice", "subdivide works on octree lattices");
  if (level && *level > shape.subdividable)
    checks.fail(pointer + "/level", "lattice '" + lattice + "' has octree levels 0 to " +
                                        std::to_string(shape.subdividable) +
                                        " (a level made by subdivide cannot be subdivided again)");
  check_cell_selection(cells, level.value_or(shape.subdividable));
  ++shape.levels;
}

void SubdivideStep::run(Scene& scene, StepContext& ctx) const {
  // The script checks made sure that the lattice is an octree lattice (subdividable).
  OctreeLattice& target = dynamic_cast<OctreeLattice&>(scene.deformer(lattice));
  const int l = level.value_or(target.num_grid_levels() - 1);
  std::vector<std::int32_t> picked;
  for (std::size_t c : select_octree_cells(cells, target, l)) picked.push_back(static_cast<std::int32_t>(c));
  const int made = target.subdivide(l, picked);
  nlohmann::json ids = nlohmann::json::array();
  for (std::int32_t c : picked) ids.push_back(write_value(target.complex(l).cells[static_cast<std::size_t>(c)]));
  ctx.stats["lattice"] = lattice;
  ctx.stats["level"] = l;
  ctx.stats["new_level"] = made;
  ctx.stats["cells_subdivided"] = picked.size();
  ctx.stats["cell_ids"] = ids;
  ctx.stats["points"] = target.num_points(made);
  ctx.stats["cells"] = target.num_cells(made);
  ctx.summary = "subdivide '" + lattice + "' level " + std::to_string(l) + ": " + format_count(picked.size()) +
                " cells, new level " + std::to_string(made) + " (" + format_count(target.num_cells(made)) + " cells, " +
                format_count(target.num_points(made)) + " points)";
}

}  // namespace

const OpInfo& subdivide_op() {
  static const OpDecl<SubdivideStep> op{
      "subdivide",
      "Local subdivision (Ono et al. Figure 3) of chosen cells of an octree level: a new level where those cells "
      "are split in eight and their neighbours keep their shape with split faces and edges.",
      subdivide_keys()};
  return op;
}

}  // namespace ffd
