// A deterministic software renderer: a mesh's polygons (fanned into triangles) drawn
// with a z-buffer, shaded, from a camera fitted to what is drawn.
//
// - Coverage is decided in integers (screen positions in 1/256 pixel, edge functions
//   with the top-left rule), and depth ties go to the earlier triangle, so a pixel's
//   triangle does not depend on how the image is split among threads.
// - Shading is deferred: each pixel keeps its triangle and barycentric coordinates and
//   is shaded once, with +, −, ×, ÷ and √ only (render.cpp is built without FMA
//   contraction), so the same mesh gives the same bytes on every thread count and on
//   every x86-64 machine.
// - Lighting is two-sided (a mesh's orientation is not assumed): ambient plus Lambert
//   from a light above and to the left of the viewer.
// - Overlays (lattice control nets) are drawn over the shaded mesh: edges as 1-pixel
//   lines, points as 3 × 3 squares.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "mesh/mesh.h"
#include "render/image.h"

namespace ffd {

/// What colours the mesh: grey (shade), the view-space normal as RGB (normals), each
/// vertex's refinement level (level: the save op's level colours; for a mesh read from a
/// file, which keeps no levels, its vertex colours, which such a save wrote), or given
/// vertex colours.
enum class ColorMode { Shade, Normals, Level };

struct RenderOptions {
  int width = 1280;
  int height = 960;
  /// The camera's direction from the model's centre: azimuth about +Y from +Z toward +X,
  /// elevation above the XZ plane, in degrees (Y is up, as in OBJ and glTF).
  double azimuth_deg = 45;
  double elevation_deg = 30;
  bool perspective = false;  // else orthographic
  bool flat = false;         // face normals, else vertex normals interpolated
  ColorMode color = ColorMode::Shade;
  Rgb background{255, 255, 255};
  int threads = 0;  // 0: OpenMP's default
};

/// Lines and points drawn over the mesh, in world space (a lattice's control net).
struct Overlay {
  std::vector<Eigen::Vector3d> points;
  std::vector<std::array<std::uint32_t, 2>> edges;  // indices into points
  Rgb edge_color{40, 90, 200};
  Rgb point_color{200, 40, 40};
};

/// Sets azimuth and elevation from "iso", "front", "side", "top" or "AZ,EL" (degrees).
/// \throw InputError naming `view` otherwise.
void set_view(RenderOptions& options, const std::string& view);
/// Parses "WxH" (each 16 .. 16384). \throw InputError otherwise.
void set_size(RenderOptions& options, const std::string& size);

/// Renders `mesh` at its current positions. `vertex_colors` (one RGB in [0,1] per
/// vertex) replaces the colour mode when not null. The camera fits the mesh and every
/// overlay point, with a margin of 4% of the image.
Image render_mesh(const Mesh& mesh, const RenderOptions& options,
                  const std::vector<Eigen::Vector3f>* vertex_colors = nullptr,
                  const std::vector<Overlay>& overlays = {});

}  // namespace ffd
