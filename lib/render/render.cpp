#include "render/render.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "common/errors.h"
#include "remesh/adaptive_remesher.h"

namespace ffd {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr std::int64_t kSub = 256;  // sub-pixel steps per pixel
constexpr int kBand = 16;           // rows per band of the rasterizer's work split

struct V3 {
  double x = 0, y = 0, z = 0;
};
V3 operator-(V3 a, V3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
double dot(V3 a, V3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
V3 cross(V3 a, V3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
V3 normalized(V3 a) {
  const double n = std::sqrt(dot(a, a));
  return n > 0 ? V3{a.x / n, a.y / n, a.z / n} : V3{0, 0, 1};
}

// sin and cos of `deg` degrees by their Taylor series after reduction to [-45°, 45°]:
// libm's may take a different code path on another CPU, and the picture must not.
void sincos_deg(double deg, double& s, double& c) {
  deg = std::fmod(deg, 360.0);
  if (deg < 0) deg += 360.0;
  const int quadrant = static_cast<int>(std::floor((deg + 45.0) / 90.0)) % 4;
  const double x = (deg - 90.0 * std::floor((deg + 45.0) / 90.0)) * (kPi / 180.0);
  double ts = x, tc = 1, sum_s = x, sum_c = 1;
  for (int k = 1; k < 12; ++k) {
    ts *= -x * x / ((2 * k) * (2 * k + 1));
    tc *= -x * x / ((2 * k - 1) * (2 * k));
    sum_s += ts;
    sum_c += tc;
  }
  const double ss[4] = {sum_s, sum_c, -sum_s, -sum_c}, cc[4] = {sum_c, -sum_s, -sum_c, sum_s};
  s = ss[quadrant];
  c = cc[quadrant];
}

// The view: an orthonormal frame looking at `center`, and the map to pixels.
struct Camera {
  V3 right, up, back, center;
  bool perspective = false;
  double distance = 0;       // perspective: from the camera to the centre
  double scale = 1, mid_x = 0, mid_y = 0;
  int width = 0, height = 0;

  // View-plane coordinates before fitting (perspective: divided by depth), and the
  // depth key (smaller is nearer; perspective: −1/depth, affine on the screen).
  void project(V3 p, double& x, double& y, double& key) const {
    const V3 d = p - center;
    x = dot(d, right);
    y = dot(d, up);
    const double z = dot(d, back);
    if (!perspective) {
      key = -z;
      return;
    }
    const double depth = std::max(distance - z, 1e-9 * distance);
    x /= depth;
    y /= depth;
    key = -1.0 / depth;
  }
  double screen_x(double x) const { return 0.5 * width + (x - mid_x) * scale; }
  double screen_y(double y) const { return 0.5 * height - (y - mid_y) * scale; }
};

V3 col(const ConstVec3Array& a, std::size_t i) { return {a(0, i), a(1, i), a(2, i)}; }

// Calls fn(p) for every point the camera fits: the mesh's vertices, then the overlays'.
template <class Fn>
void for_each_fitted(const Mesh& mesh, const std::vector<Overlay>& overlays, Fn fn) {
  const ConstVec3Array p = mesh.positions();
  for (std::size_t i = 0; i < mesh.num_vertices(); ++i) fn(col(p, i));
  for (const Overlay& ov : overlays)
    for (const Eigen::Vector3d& q : ov.points) fn(V3{q.x(), q.y(), q.z()});
}

// Orients the camera and fits the mesh and the overlays' points into the image.
Camera fit_camera(const Mesh& mesh, const std::vector<Overlay>& overlays, const RenderOptions& o) {
  Camera cam;
  cam.width = o.width;
  cam.height = o.height;
  cam.perspective = o.perspective;
  V3 lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
  std::size_t count = 0;
  for_each_fitted(mesh, overlays, [&](V3 p) {
    lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
    hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
    ++count;
  });
  if (count == 0) lo = hi = V3{};
  cam.center = {0.5 * (lo.x + hi.x), 0.5 * (lo.y + hi.y), 0.5 * (lo.z + hi.z)};
  double sa, ca, se, ce;
  sincos_deg(o.azimuth_deg, sa, ca);
  sincos_deg(o.elevation_deg, se, ce);
  cam.back = {ce * sa, se, ce * ca};
  V3 r = cross(V3{0, 1, 0}, cam.back);
  if (dot(r, r) < 1e-12) r = V3{ca, 0, -sa};  // looking straight down or up
  cam.right = normalized(r);
  cam.up = cross(cam.back, cam.right);
  double radius = 0;
  for_each_fitted(mesh, overlays, [&](V3 p) { radius = std::max(radius, dot(p - cam.center, p - cam.center)); });
  radius = std::sqrt(radius);
  cam.distance = (radius > 0 ? radius : 1.0) / 0.25881904510252074;  // sin 15°: a 30° field of view
  double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
  for_each_fitted(mesh, overlays, [&](V3 p) {
    double x, y, k;
    cam.project(p, x, y, k);
    x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
  });
  if (count == 0) x0 = x1 = y0 = y1 = 0;
  cam.mid_x = 0.5 * (x0 + x1);
  cam.mid_y = 0.5 * (y0 + y1);
  const double span_x = std::max(x1 - x0, 1e-300), span_y = std::max(y1 - y0, 1e-300);
  cam.scale = std::min(0.92 * o.width / span_x, 0.92 * o.height / span_y);
  return cam;
}

// A vertex on the screen: fixed-point position, depth key and the view-space normal.
struct ScreenVertex {
  std::int64_t x = 0, y = 0;
  double key = 0, q = 1;  // q: 1/depth for perspective-correct interpolation (1 if orthographic)
};

std::int64_t fixed(double v) {
  const double limit = 1e6;  // pixels: far outside any image, and edge products stay below 2^60
  return static_cast<std::int64_t>(std::floor(std::clamp(v, -limit, limit) * kSub + 0.5));
}

std::int64_t floor_div(std::int64_t a, std::int64_t b) { return a >= 0 ? a / b : -((-a + b - 1) / b); }
std::int64_t ceil_div(std::int64_t a, std::int64_t b) { return -floor_div(-a, b); }

}  // namespace

namespace {

// What the z-buffer keeps per pixel: the nearest triangle and its barycentric weights
// of corners 1 and 2 (corner 0's is the rest).
struct Fragments {
  int width = 0, height = 0;
  std::vector<double> key;
  std::vector<std::uint32_t> tri;  // kNone where no triangle covers the pixel
  std::vector<float> b1, b2;
  static constexpr std::uint32_t kNone = 0xffffffffu;
};

// Whether edge u→v owns the pixels exactly on it (the top-left rule): of the two
// triangles sharing an edge, which run it in opposite directions, exactly one does.
bool owns_edge(const ScreenVertex& u, const ScreenVertex& v) {
  const std::int64_t dy = v.y - u.y;
  return dy < 0 || (dy == 0 && v.x - u.x > 0);
}

std::int64_t edge(const ScreenVertex& u, const ScreenVertex& v, std::int64_t px, std::int64_t py) {
  return (v.x - u.x) * (py - u.y) - (v.y - u.y) * (px - u.x);
}

// Draws triangle t into rows [row0, row1) of the fragments.
void rasterize(const std::array<std::uint32_t, 3>& tv, std::uint32_t t, const std::vector<ScreenVertex>& sv,
               int row0, int row1, Fragments& f) {
  std::array<const ScreenVertex*, 3> v{&sv[tv[0]], &sv[tv[1]], &sv[tv[2]]};
  std::int64_t area = edge(*v[0], *v[1], v[2]->x, v[2]->y);
  if (area == 0) return;
  const bool swapped = area < 0;
  if (swapped) std::swap(v[1], v[2]), area = -area;
  const std::int64_t xmin = std::min({v[0]->x, v[1]->x, v[2]->x}), xmax = std::max({v[0]->x, v[1]->x, v[2]->x});
  const std::int64_t ymin = std::min({v[0]->y, v[1]->y, v[2]->y}), ymax = std::max({v[0]->y, v[1]->y, v[2]->y});
  const std::int64_t x0 = std::max<std::int64_t>(0, ceil_div(xmin - kSub / 2, kSub));
  const std::int64_t x1 = std::min<std::int64_t>(f.width - 1, floor_div(xmax - kSub / 2, kSub));
  const std::int64_t y0 = std::max<std::int64_t>(row0, ceil_div(ymin - kSub / 2, kSub));
  const std::int64_t y1 = std::min<std::int64_t>(row1 - 1, floor_div(ymax - kSub / 2, kSub));
  if (x0 > x1 || y0 > y1) return;
  const std::int64_t bias0 = owns_edge(*v[1], *v[2]) ? 0 : -1, bias1 = owns_edge(*v[2], *v[0]) ? 0 : -1,
                     bias2 = owns_edge(*v[0], *v[1]) ? 0 : -1;
  const double inv_area = 1.0 / static_cast<double>(area);
  for (std::int64_t y = y0; y <= y1; ++y) {
    const std::int64_t py = y * kSub + kSub / 2, px = x0 * kSub + kSub / 2;
    std::int64_t w0 = edge(*v[1], *v[2], px, py), w1 = edge(*v[2], *v[0], px, py), w2 = edge(*v[0], *v[1], px, py);
    const std::int64_t d0 = -(v[2]->y - v[1]->y) * kSub, d1 = -(v[0]->y - v[2]->y) * kSub, d2 = -(v[1]->y - v[0]->y) * kSub;
    std::size_t p = static_cast<std::size_t>(y) * f.width + x0;
    for (std::int64_t x = x0; x <= x1; ++x, ++p, w0 += d0, w1 += d1, w2 += d2) {
      if (w0 + bias0 < 0 || w1 + bias1 < 0 || w2 + bias2 < 0) continue;
      const double a = w0 * inv_area, b = w1 * inv_area, c = w2 * inv_area;
      const double key = a * v[0]->key + b * v[1]->key + c * v[2]->key;
      if (!(key < f.key[p])) continue;  // ties: the earlier triangle stays
      f.key[p] = key;
      f.tri[p] = t;
      f.b1[p] = static_cast<float>(swapped ? c : b);  // weights of the original corners 1, 2
      f.b2[p] = static_cast<float>(swapped ? b : c);
    }
  }
}

// The z-buffer pass: bands of rows in parallel, every band taking the triangles in order.
Fragments draw_triangles(const std::vector<std::array<std::uint32_t, 3>>& tris, const std::vector<ScreenVertex>& sv,
                         const RenderOptions& o) {
  Fragments f;
  f.width = o.width;
  f.height = o.height;
  const std::size_t n = static_cast<std::size_t>(o.width) * o.height;
  f.key.assign(n, std::numeric_limits<double>::infinity());
  f.tri.assign(n, Fragments::kNone);
  f.b1.assign(n, 0.0f);
  f.b2.assign(n, 0.0f);
  std::vector<std::array<std::int32_t, 2>> rows(tris.size());  // each triangle's pixel rows
  const auto count = static_cast<std::int64_t>(tris.size());
#pragma omp parallel for schedule(static)
  for (std::int64_t t = 0; t < count; ++t) {
    const std::int64_t lo = std::min({sv[tris[t][0]].y, sv[tris[t][1]].y, sv[tris[t][2]].y});
    const std::int64_t hi = std::max({sv[tris[t][0]].y, sv[tris[t][1]].y, sv[tris[t][2]].y});
    rows[t] = {static_cast<std::int32_t>(std::clamp<std::int64_t>(floor_div(lo, kSub), -1, o.height)),
               static_cast<std::int32_t>(std::clamp<std::int64_t>(floor_div(hi, kSub), -1, o.height))};
  }
  // Bin the triangles by band (in triangle order within each band), then draw the bands.
  const int bands = (o.height + kBand - 1) / kBand;
  std::vector<std::size_t> start(bands + 1, 0);
  auto band_range = [&](std::int64_t t, int& b0, int& b1) {
    b0 = std::max(0, rows[t][0]) / kBand;
    b1 = std::min(o.height - 1, rows[t][1]) / kBand;
    if (rows[t][1] < 0 || rows[t][0] >= o.height) b1 = b0 - 1;
  };
  for (std::int64_t t = 0; t < count; ++t) {
    int b0, b1;
    band_range(t, b0, b1);
    for (int b = b0; b <= b1; ++b) ++start[b + 1];
  }
  for (int b = 0; b < bands; ++b) start[b + 1] += start[b];
  std::vector<std::uint32_t> binned(start[bands]);
  std::vector<std::size_t> fill(start.begin(), start.end() - 1);
  for (std::int64_t t = 0; t < count; ++t) {
    int b0, b1;
    band_range(t, b0, b1);
    for (int b = b0; b <= b1; ++b) binned[fill[b]++] = static_cast<std::uint32_t>(t);
  }
#pragma omp parallel for schedule(dynamic, 1)
  for (int band = 0; band < bands; ++band) {
    const int row0 = band * kBand, row1 = std::min(o.height, row0 + kBand);
    for (std::size_t k = start[band]; k < start[band + 1]; ++k) rasterize(tris[binned[k]], binned[k], sv, row0, row1, f);
  }
  return f;
}

}  // namespace

namespace {

std::uint8_t to_byte(double c) { return static_cast<std::uint8_t>(std::floor(std::clamp(c, 0.0, 1.0) * 255.0 + 0.5)); }

// What the shading pass reads per vertex, in view space.
struct ShadeInput {
  const std::vector<std::array<std::uint32_t, 3>>* tris = nullptr;
  std::vector<V3> view_pos, view_normal;
  std::vector<ScreenVertex>* screen = nullptr;
  const std::vector<Eigen::Vector3f>* colors = nullptr;  // per vertex, or null
};

// The colour of pixel p from its triangle: the interpolated (or face) normal lit two-sided.
Rgb shade_pixel(const Fragments& f, std::size_t p, const ShadeInput& in, const RenderOptions& o) {
  const std::array<std::uint32_t, 3>& t = (*in.tris)[f.tri[p]];
  double w[3] = {1.0 - double(f.b1[p]) - double(f.b2[p]), f.b1[p], f.b2[p]};
  if (o.perspective) {  // screen-space weights to perspective-correct ones
    double sum = 0;
    for (int k = 0; k < 3; ++k) sum += w[k] *= (*in.screen)[t[k]].q;
    for (double& x : w) x /= sum;
  }
  V3 n;
  if (o.flat) {
    n = cross(in.view_pos[t[1]] - in.view_pos[t[0]], in.view_pos[t[2]] - in.view_pos[t[0]]);
  } else {
    for (int k = 0; k < 3; ++k)
      n = {n.x + w[k] * in.view_normal[t[k]].x, n.y + w[k] * in.view_normal[t[k]].y, n.z + w[k] * in.view_normal[t[k]].z};
  }
  n = normalized(n);
  if (o.color == ColorMode::Normals && !in.colors) {
    const double s = n.z < 0 ? -1 : 1;  // the side facing the viewer
    return {to_byte(0.5 + 0.5 * s * n.x), to_byte(0.5 + 0.5 * s * n.y), to_byte(0.5 + 0.5 * s * n.z)};
  }
  static const V3 light = normalized(V3{-0.35, 0.55, 0.76});
  const double intensity = 0.2 + 0.8 * std::fabs(dot(n, light));
  double c[3] = {0.8, 0.8, 0.8};
  if (in.colors) {
    for (int ch = 0; ch < 3; ++ch) {
      c[ch] = 0;
      for (int k = 0; k < 3; ++k) c[ch] += w[k] * double((*in.colors)[t[k]][ch]);
    }
  }
  return {to_byte(c[0] * intensity), to_byte(c[1] * intensity), to_byte(c[2] * intensity)};
}

void shade(const Fragments& f, const ShadeInput& in, const RenderOptions& o, Image& image) {
#pragma omp parallel for schedule(static)
  for (int y = 0; y < f.height; ++y)
    for (int x = 0; x < f.width; ++x) {
      const std::size_t p = static_cast<std::size_t>(y) * f.width + x;
      if (f.tri[p] != Fragments::kNone) image.set(x, y, shade_pixel(f, p, in, o));
    }
}

// A line from (x0, y0) to (x1, y1) in pixels (Bresenham), clipped to the image.
void draw_line(Image& image, std::int64_t x0, std::int64_t y0, std::int64_t x1, std::int64_t y1, Rgb color) {
  const std::int64_t dx = std::llabs(x1 - x0), dy = -std::llabs(y1 - y0);
  const std::int64_t sx = x0 < x1 ? 1 : -1, sy = y0 < y1 ? 1 : -1;
  std::int64_t err = dx + dy;
  for (std::int64_t steps = 0; steps <= dx - dy; ++steps) {
    if (image.contains(static_cast<int>(x0), static_cast<int>(y0))) image.set(int(x0), int(y0), color);
    if (x0 == x1 && y0 == y1) break;
    const std::int64_t e2 = 2 * err;
    if (e2 >= dy) err += dy, x0 += sx;
    if (e2 <= dx) err += dx, y0 += sy;
  }
}

void draw_overlays(Image& image, const Camera& cam, const std::vector<Overlay>& overlays) {
  for (const Overlay& ov : overlays) {
    std::vector<std::array<std::int64_t, 2>> px(ov.points.size());
    for (std::size_t i = 0; i < ov.points.size(); ++i) {
      double x, y, k;
      cam.project({ov.points[i].x(), ov.points[i].y(), ov.points[i].z()}, x, y, k);
      px[i] = {static_cast<std::int64_t>(std::floor(std::clamp(cam.screen_x(x), -1e6, 1e6))),
               static_cast<std::int64_t>(std::floor(std::clamp(cam.screen_y(y), -1e6, 1e6)))};
    }
    for (const auto& e : ov.edges)
      if (e[0] < px.size() && e[1] < px.size())
        draw_line(image, px[e[0]][0], px[e[0]][1], px[e[1]][0], px[e[1]][1], ov.edge_color);
    for (const auto& p : px)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx)
          if (image.contains(int(p[0] + dx), int(p[1] + dy))) image.set(int(p[0] + dx), int(p[1] + dy), ov.point_color);
  }
}

}  // namespace

Image render_mesh(const Mesh& mesh, const RenderOptions& o, const std::vector<Eigen::Vector3f>* vertex_colors,
                  const std::vector<Overlay>& overlays) {
  const std::size_t n = mesh.num_vertices();
  const Camera cam = fit_camera(mesh, overlays, o);
  ShadeInput in;
  std::vector<ScreenVertex> screen(n);
  // Flat shading reads view-space positions (face normals), smooth shading vertex normals.
  (o.flat ? in.view_pos : in.view_normal).resize(n);
#pragma omp parallel for schedule(static)
  for (std::int64_t i = 0; i < static_cast<std::int64_t>(n); ++i) {
    const V3 p = col(mesh.positions(), i);
    double x, y, key;
    cam.project(p, x, y, key);
    screen[i] = {fixed(cam.screen_x(x)), fixed(cam.screen_y(y)), key, o.perspective ? -key : 1.0};
    const V3 d = p - cam.center, nw = col(mesh.normals(), i);
    if (o.flat) in.view_pos[i] = {dot(d, cam.right), dot(d, cam.up), dot(d, cam.back)};
    else in.view_normal[i] = {dot(nw, cam.right), dot(nw, cam.up), dot(nw, cam.back)};
  }
  const std::vector<std::array<std::uint32_t, 3>> tris = fan_triangles(mesh.elements());
  in.tris = &tris;
  in.screen = &screen;
  std::vector<Eigen::Vector3f> levels;
  if (!vertex_colors && o.color == ColorMode::Level) {
    if (mesh.vertex_levels().empty() && mesh.has_colors()) {
      vertex_colors = &mesh.colors();  // a file saved with "colors": "level" holds them as colours
    } else {
      int top = 1;  // as save's level colours: level 1 is the first colour past grey
      for (int level : vertex_levels(mesh)) top = std::max(top, level);
      levels = level_colors(mesh, top);
      vertex_colors = &levels;
    }
  }
  in.colors = vertex_colors && vertex_colors->size() == n ? vertex_colors : nullptr;
  Image image(o.width, o.height, o.background);
  shade(draw_triangles(tris, screen, o), in, o, image);
  draw_overlays(image, cam, overlays);
  return image;
}

void set_view(RenderOptions& o, const std::string& view) {
  if (view == "iso") o.azimuth_deg = 45, o.elevation_deg = 30;
  else if (view == "front") o.azimuth_deg = 0, o.elevation_deg = 0;
  else if (view == "side") o.azimuth_deg = 90, o.elevation_deg = 0;
  else if (view == "top") o.azimuth_deg = 0, o.elevation_deg = 90;
  else {
    double az = 0, el = 0;
    char extra = 0;
    if (std::sscanf(view.c_str(), "%lf,%lf%c", &az, &el, &extra) != 2 || !std::isfinite(az) || !std::isfinite(el) ||
        el < -90 || el > 90)
      throw InputError("--view " + view + ": expected iso, front, side, top or AZ,EL in degrees (EL in -90..90)");
    o.azimuth_deg = az, o.elevation_deg = el;
  }
}

void set_size(RenderOptions& o, const std::string& size) {
  int w = 0, h = 0;
  char extra = 0;
  if (std::sscanf(size.c_str(), "%dx%d%c", &w, &h, &extra) != 2 || w < 16 || h < 16 || w > 16384 || h > 16384)
    throw InputError("--size " + size + ": expected WxH with each side 16 .. 16384, e.g. 1280x960");
  o.width = w, o.height = h;
}

}  // namespace ffd
