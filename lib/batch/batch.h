// `ffdtool batch`: one script over many meshes, each in a child process of its own (so
// that a crash, a timeout or running out of memory is that item's failure alone), several
// at once, sharded across a job array, resumable, with a results log.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "batch/batch_items.h"
#include "common/progress.h"

namespace ffd {

struct BatchOptions {
  std::string script;
  std::vector<std::string> inputs;   // files, folders, @lists
  std::string output_folder;
  std::size_t jobs = 0;              // meshes at once; 0: one per core
  std::optional<Shard> shard;        // else from the environment, else all
  bool resume = false;               // skip items done with this input and script
  std::string format;                // output extension; "": the input's
  bool recursive = false;
  double timeout_s = 0;              // per item; 0: none
  std::size_t max_memory = 0;        // per item, bytes of address space; 0: none
  std::string runner;                // the ffdtool that runs items; "": this one
  ProgressMode progress = ProgressMode::None;  // a live line or events on stderr
  std::string junit;                 // a JUnit XML report of the items, written at the end; "": none
};

/// Runs the batch and returns its exit code: the worst of its items' (0, 2 or 3). Every
/// item's output is what `ffdtool run` writes for it (its saves under OUTDIR/name/), and
/// a line of the results log; with `junit`, the items (skipped ones too) as a JUnit XML
/// report once they have ended, or once a failure stopped the batch. \throw InputError before any work for a bad script, bad
/// inputs or options; IoError if the output folder or the log cannot be written.
int run_batch(const BatchOptions& options);

}  // namespace ffd
