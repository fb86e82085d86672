#include "render/heatmap.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "render/text.h"

namespace ffd {

namespace {

// matplotlib's viridis at t = 0, 0.1, …, 1 (its published 11-stop table).
constexpr unsigned kViridis[11] = {0x440154, 0x482475, 0x414487, 0x355f8d, 0x2a788e, 0x21918c,
                                   0x22a884, 0x44bf70, 0x7ad151, 0xbddf26, 0xfde725};
const Eigen::Vector3f kGrey(0.8f, 0.8f, 0.8f);

Eigen::Vector3f stop(int i) {
  const unsigned c = kViridis[i];
  return Eigen::Vector3f(float((c >> 16) & 255), float((c >> 8) & 255), float(c & 255)) / 255.0f;
}

Rgb to_rgb(const Eigen::Vector3f& c) {
  auto b = [](float v) { return static_cast<std::uint8_t>(std::floor(std::clamp(v, 0.0f, 1.0f) * 255.0f + 0.5f)); };
  return {b(c.x()), b(c.y()), b(c.z())};
}

std::string number(const char* label, double value) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%s %.4g", label, value);
  return buf;
}

// The legend: a vertical bar from the tolerance (bottom) to the max (top), labelled.
void draw_legend(Image& image, double tolerance, double max_distance, int scale) {
  const int bar_w = 14 * scale, bar_h = std::max(40, image.height / 2);
  const int x0 = image.width - bar_w - 8 * scale - text_width("0.0000e-00", scale), y0 = (image.height - bar_h) / 2;
  for (int y = 0; y < bar_h; ++y) {
    const Rgb c = to_rgb(viridis(1.0 - double(y) / std::max(1, bar_h - 1)));
    for (int x = 0; x < bar_w; ++x)
      if (image.contains(x0 + x, y0 + y)) image.set(x0 + x, y0 + y, c);
  }
  const Rgb ink{20, 20, 20}, paper{255, 255, 255};
  char top[32], bottom[32];
  std::snprintf(top, sizeof top, "%.4g", max_distance);
  std::snprintf(bottom, sizeof bottom, "%.4g", tolerance);
  draw_text_box(image, x0 + bar_w + 4 * scale, y0, top, ink, paper, scale);
  draw_text_box(image, x0 + bar_w + 4 * scale, y0 + bar_h - text_height(scale), bottom, ink, paper, scale);
}

}  // namespace

Eigen::Vector3f viridis(double t) {
  if (!(t > 0)) return stop(0);
  if (t >= 1) return stop(10);
  const double x = t * 10;
  const int i = std::min(9, static_cast<int>(x));
  const float f = static_cast<float>(x - i);
  return stop(i) * (1.0f - f) + stop(i + 1) * f;
}

std::vector<Eigen::Vector3f> distance_colors(const std::vector<double>& distances, double tolerance,
                                             double max_distance) {
  std::vector<Eigen::Vector3f> out(distances.size(), kGrey);
  const double span = max_distance - tolerance;
  for (std::size_t v = 0; v < distances.size(); ++v) {
    const double d = distances[v];
    if (std::isnan(d) || d <= tolerance) continue;
    out[v] = viridis(span > 0 ? (d - tolerance) / span : 1.0);
  }
  return out;
}

Image render_heatmap(const Mesh& b, const std::vector<double>& distances, double tolerance, double max_distance,
                     double mean_distance, const RenderOptions& options) {
  const std::vector<Eigen::Vector3f> colors = distance_colors(distances, tolerance, max_distance);
  Image image = render_mesh(b, options, &colors);
  const int scale = std::max(1, image.height / 320);
  const std::string label =
      number("max", max_distance) + "   " + number("mean", mean_distance) + "   " + number("tolerance", tolerance);
  draw_text_box(image, 4 * scale, 4 * scale, label, Rgb{20, 20, 20}, Rgb{255, 255, 255}, scale);
  const bool differs = std::any_of(distances.begin(), distances.end(), [&](double d) { return d > tolerance; });
  if (differs) draw_legend(image, tolerance, max_distance, scale);
  return image;
}

}  // namespace ffd
