// `ffdtool compare DIR_A DIR_B`: every mesh file of one folder against the file of the
// same relative path in the other, several pairs at once (docs/architecture.md,
// "Comparing meshes").
#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "mesh/mesh_compare.h"

namespace ffd {

/// One relative path of the two folders.
struct PairResult {
  enum class Status { Same, Different, OnlyInA, OnlyInB, Error };
  std::string path;  // relative to both folders, '/'-separated
  Status status = Status::Same;
  MeshDifference difference;  // for Same and Different (without its per-vertex distances)
  std::string message;        // Different: what differs; Error: the error line
  double ms = 0;              // reading and comparing the pair
};

struct FolderCompareOptions {
  CompareOptions compare;
  bool recursive = false;  // also the subfolders' files
  std::size_t jobs = 0;    // pairs at once; 0: one per core
  /// Called, from the thread that compared it, for a differing pair with the B mesh and
  /// its difference (per-vertex distances included): `compare --heatmap-dir`.
  std::function<void(const PairResult&, const Mesh& b)> on_different;
};

struct FolderComparison {
  std::vector<PairResult> pairs;  // sorted by path
  std::size_t same = 0, different = 0, only_in_a = 0, only_in_b = 0, errors = 0;
  std::size_t worst = 0;          // the pair with the largest distance (pairs.size(): none)
};

/// Compares the folders' meshes pair by pair. The result does not depend on `jobs`.
/// \throw InputError if either is not a folder.
FolderComparison compare_folders(const std::string& a, const std::string& b, const FolderCompareOptions& options);

/// One line of what differs, for a Different pair: "hausdorff distance 0.012 > tolerance 0.001".
std::string difference_line(const MeshDifference& d, double tolerance);

}  // namespace ffd
