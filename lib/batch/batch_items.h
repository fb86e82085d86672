// The items of a batch: which meshes, in which order, written where, and which of them
// this shard takes (docs/architecture.md, "Batches").
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace ffd {

/// One mesh of a batch.
struct BatchItem {
  std::size_t index = 0;    // position in the sorted list of all items
  std::string input;        // the mesh file, as found
  std::string name;         // its stem; "pig_off" for pig.off when another input is pig.stl
  std::string output;       // OUTDIR/FILE (the input's file name), or OUTDIR/name.FORMAT
  std::string save_folder;  // OUTDIR/name: the script's save paths are relative to it
};

/// The meshes the INPUT arguments name: files, folders (their files with a mesh
/// extension; with `recursive`, their subfolders' too) and @lists (one path a line, as
/// written: relative to the working folder), sorted by path, leaving out files inside
/// `output_folder` (a batch's own outputs, when it writes inside an input folder), each written to
/// `output_folder`/FILE, its input's file name, or with a `format` to `output_folder`/name.FORMAT.
/// An item's name is its file's stem, unless another input has the same stem: then both
/// are named by their file names with the extension's dot made '_' (pig.off and pig.stl
/// are pig_off and pig_stl), so that their save folders (and outputs of one format) stay apart.
/// \throw InputError for a missing input, a file without a mesh extension, two inputs
/// whose names are still the same (a/pig.off and b/pig.off; pig.off, pig.stl and
/// pig_off.obj), an output that would overwrite an input, or no mesh at all.
std::vector<BatchItem> batch_items(const std::vector<std::string>& inputs, bool recursive,
                                   const std::string& output_folder, const std::string& format);

/// The mesh files (by extension) under `folder`, with `recursive` its subfolders' too:
/// paths relative to it, '/'-separated, sorted. \throw InputError if it is not a folder
/// or cannot be listed.
std::vector<std::string> mesh_files_under(const std::string& folder, bool recursive);

/// Shard `index` of `count`: the items whose index ≡ index (mod count).
struct Shard {
  std::size_t index = 0, count = 1;
  std::string source;  // "--shard", "SLURM_ARRAY_TASK_ID", "JOB_COMPLETION_INDEX"
};

/// "I/N" with 0 <= I < N. \throw InputError otherwise.
Shard parse_shard(const std::string& text);

/// The shard a Slurm job array task (SLURM_ARRAY_TASK_ID, _MIN, _STEP, _COUNT) or a
/// Kubernetes Indexed Job (JOB_COMPLETION_INDEX with FFD_SHARD_COUNT) is, if either.
/// \throw InputError for values that are not a shard.
std::optional<Shard> shard_from_environment();

/// The items of `all` in `shard`.
std::vector<BatchItem> shard_items(const std::vector<BatchItem>& all, const Shard& shard);

}  // namespace ffd
