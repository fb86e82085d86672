// The CLI's pictures: `ffdtool render` and `compare --heatmap` (lib/render).
#pragma once

#include <CLI/CLI.hpp>
#include <string>

#include "mesh/mesh.h"

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

/// Writes `compare`'s heat map of b against a to `path`.
void write_heatmap(const std::string& path, const ffd::Mesh& a, const ffd::Mesh& b, bool hausdorff, double tolerance,
                   const PictureArgs& args);

}  // namespace ffdcli
