#include "pictures.h"

#include <omp.h>

#include <algorithm>
#include <cmath>

#include "common/atomic_file.h"
#include "common/errors.h"
#include "mesh/mesh_compare.h"
#include "mesh/mesh_io.h"
#include "render/heatmap.h"
#include "render/png_io.h"
#include "render/render.h"

namespace ffdcli {

namespace {

ffd::RenderOptions render_options(const PictureArgs& args) {
  ffd::RenderOptions o;
  ffd::set_size(o, args.size);
  ffd::set_view(o, args.view);
  o.color = args.color == "normals" ? ffd::ColorMode::Normals
            : args.color == "level" ? ffd::ColorMode::Level : ffd::ColorMode::Shade;
  o.perspective = args.camera == "perspective";
  o.flat = args.flat;
  o.threads = args.threads;
  if (args.threads > 0) omp_set_num_threads(args.threads);
  return o;
}

// Checks `path` is a .png in an existing folder, before any work.
void check_png_path(const std::string& path, const char* what) {
  if (!ffd::has_png_extension(path)) throw ffd::InputError(ffd::At{path}, std::string(what) + " is written as PNG: give it the extension .png");
  ffd::require_output_folder(path, what);
}

void save_png(const std::string& path, const ffd::Image& image) {
  ffd::write_file_atomically(path, [&](std::ostream& os) { ffd::write_png(os, image); });
}

}  // namespace

void add_picture_options(CLI::App* command, PictureArgs& args) {
  command->add_option("--size", args.size, "Picture size WxH")->capture_default_str();
  command->add_option("--view", args.view, "iso, front, side, top, or AZ,EL in degrees (Y up)")->capture_default_str();
}

CLI::App* add_render(CLI::App& app, PictureArgs& args) {
  CLI::App* cmd = app.add_subcommand("render", "Draw a mesh to a PNG (software z-buffer, same bytes on any machine)");
  cmd->add_option("mesh", args.mesh, "Mesh file")->required();
  cmd->add_option("-o,--output", args.output, "PNG file")->required();
  add_picture_options(cmd, args);
  cmd->add_option("--color", args.color, "shade: grey; normals: normal as RGB; level: refinement level (a file's vertex colours, as save writes levels)")
      ->check(CLI::IsMember({"shade", "normals", "level"}))
      ->capture_default_str();
  cmd->add_option("--camera", args.camera, "ortho or perspective (30 degree field), fitted to the mesh")
      ->check(CLI::IsMember({"ortho", "perspective"}))
      ->capture_default_str();
  cmd->add_flag("--flat", args.flat, "Flat shading (face normals) instead of smooth");
  cmd->add_option("--threads", args.threads, "Threads (default: all cores); the picture is the same")
      ->check(CLI::NonNegativeNumber);
  return cmd;
}

int command_render(const PictureArgs& args) {
  const ffd::RenderOptions options = render_options(args);
  check_png_path(args.output, "the picture");
  const ffd::Mesh mesh = ffd::read_mesh(args.mesh);
  save_png(args.output, ffd::render_mesh(mesh, options));
  return 0;
}

void check_heatmap_path(const std::string& path) { check_png_path(path, "the heat map"); }

void write_heatmap(const std::string& path, const ffd::Mesh& b, const ffd::MeshDifference& d, double tolerance,
                   const PictureArgs& args) {
  if (d.distances.empty())
    throw ffd::InputError(ffd::At{path}, d.metric == "hausdorff"
                                             ? "the heat map needs faces on both meshes"
                                             : "the vertex metric's heat map needs the same vertex count in both "
                                               "meshes (use --metric hausdorff)");
  double max = 0, sum = 0;
  std::size_t n = 0;
  for (double x : d.distances)
    if (!std::isnan(x)) max = std::max(max, x), sum += x, ++n;
  save_png(path, ffd::render_heatmap(b, d.distances, tolerance, max, n ? sum / n : 0.0, render_options(args)));
}

}  // namespace ffdcli
