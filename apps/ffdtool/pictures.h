// The CLI's pictures: `ffdtool render` and `compare --heatmap` (lib/render).
#pragma once

#include <CLI/CLI.hpp>
#include <string>

#include "mesh/mesh.h"
#include "mesh/mesh_compare.h"

namespace ffdcli {

/// What `render` and the heat map take from the command line.
struct PictureArgs {
  std::string mesh, output;
  std::string size = "1280x960", view = "iso", color = "shade", camera = "ortho";
  bool flat = false;
  int threads = 0;
};

/// Adds `render MESH -o out.png [--size] [--view] [--color] [--camera] [--flat] [--threads]`.
CLI::App* add_render(CLI::App& app, PictureArgs& args);
/// Adds --size and --view to `command` for its picture (compare --heatmap).
void add_picture_options(CLI::App* command, PictureArgs& args);

/// Runs `render`; returns the exit code.
int command_render(const PictureArgs& args);

/// Checks `path` for `compare --heatmap` (a .png in an existing folder), before any work.
void check_heatmap_path(const std::string& path);
/// Writes `compare`'s heat map of b, coloured by `d.distances` (its distances to a), to `path`.
void write_heatmap(const std::string& path, const ffd::Mesh& b, const ffd::MeshDifference& d, double tolerance,
                   const PictureArgs& args);

}  // namespace ffdcli
