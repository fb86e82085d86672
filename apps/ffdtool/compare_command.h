// `ffdtool compare`: two meshes, or two folders of meshes pair by pair; text or JSON on
// stdout, heat maps and a JUnit report on request. Exit 0 same, 1 different, 2 bad input.
#pragma once

#include <CLI/CLI.hpp>
#include <string>

#include "mesh/mesh_compare.h"
#include "pictures.h"

namespace ffdcli {

struct CompareArgs {
  std::string a, b;
  ffd::CompareOptions compare;
  bool json = false;
  std::string heatmap, heatmap_dir, junit;
  bool recursive = false;
  std::size_t jobs = 0;
  PictureArgs picture;
};

/// Adds the `compare` subcommand and its options.
CLI::App* add_compare(CLI::App& app, CompareArgs& args);

/// Runs `compare`; returns the exit code.
int command_compare(const CompareArgs& args);

}  // namespace ffdcli
