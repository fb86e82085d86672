// Scene: what a script's steps act on (docs/architecture.md, "The data as it flows").
#pragma once

#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/atomic_file.h"
#include "mesh/cell_quality.h"
#include "mesh/halfedge_view.h"
#include "mesh/mesh.h"
#include "mesh/mesh_io.h"
#include "warp/deformer.h"
#include "warp/warp_stack.h"

namespace ffd {

struct SurfaceEditor;
/// Deletes a SurfaceEditor (surface_edits.cpp), so that this header needs only its name.
struct SurfaceEditorDelete {
  void operator()(SurfaceEditor* editor) const;
};

struct Scene {
  Mesh mesh;
  /// The halfedge view the last remesh step left, for the next one (halfedge_view.h).
  HalfedgeCache halfedges;
  WarpStack stack;
  /// Deformers (lattices of every kind) by name; owned by `stack`.
  std::map<std::string, Deformer*> deformers;
  /// Lattices frozen into the rest positions by a surface edit: name -> step pointer.
  std::map<std::string, std::string> baked;
  /// Boundary-constraint editors by name (bcm steps), driven by transform steps.
  std::map<std::string, std::unique_ptr<SurfaceEditor, SurfaceEditorDelete>> editors;

  std::string output_folder;
  /// Files written by steps, put in place only when the whole run succeeds.
  std::vector<StagedFile> staged;
  std::vector<std::string> warnings;
  /// A volume mesh's last guard verdict (script/volume_guard.h), empty before the first,
  /// and the positions and per-block verdicts it came from (a step measures again only
  /// the blocks of cells whose nodes it moved; one that moved no node keeps the verdict).
  std::optional<CellQuality> quality;
  CellQualityCache quality_cache;

  /// Write options that carry file normals through the warp stack.
  WriteOptions write_options() const;
  /// The deformer called `name` (the script checks created it before the step).
  /// \throw InputError about "lattice" if it was baked by a surface edit.
  Deformer& deformer(const std::string& name);
};

/// Refuses a volume mesh (Mesh::volume_source) for an op that changes or needs a surface
/// (`op`: "remesh", "bcm"). \throw InputError saying why.
void require_surface_mesh(const Mesh& mesh, const std::string& op);

/// What one step reports: its JSON stats object (op-specific counts) and a summary line;
/// and where it reports how far it is.
struct StepContext {
  std::string pointer;  // "/steps/3", for warnings
  nlohmann::ordered_json stats = nlohmann::ordered_json::object();
  std::string summary;
  /// The fraction of the step done, in [0, 1], for a step long enough to want it: an op
  /// forwards it to its algorithm's progress parameter. Empty when nobody listens (test
  /// before calling); calling it never changes what the step computes.
  std::function<void(double)> progress;
};

}  // namespace ffd
