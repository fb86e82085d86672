// An 8-bit RGB picture: what the renderer draws into and the PNG writer writes.
#pragma once

#include <cstdint>
#include <vector>

namespace ffd {

/// One pixel's colour, 8 bits a channel.
struct Rgb {
  std::uint8_t r = 0, g = 0, b = 0;
  bool operator==(const Rgb& o) const { return r == o.r && g == o.g && b == o.b; }
};

/// width × height pixels, row by row from the top, 3 bytes a pixel.
struct Image {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> rgb;  // size 3 · width · height

  Image() = default;
  Image(int w, int h, Rgb fill = {}) : width(w), height(h), rgb(std::size_t(3) * w * h) {
    for (std::size_t i = 0; i < rgb.size(); i += 3) {
      rgb[i] = fill.r;
      rgb[i + 1] = fill.g;
      rgb[i + 2] = fill.b;
    }
  }
  bool contains(int x, int y) const { return x >= 0 && y >= 0 && x < width && y < height; }
  Rgb at(int x, int y) const {
    const std::uint8_t* p = &rgb[3 * (std::size_t(y) * width + x)];
    return {p[0], p[1], p[2]};
  }
  void set(int x, int y, Rgb c) {
    std::uint8_t* p = &rgb[3 * (std::size_t(y) * width + x)];
    p[0] = c.r;
    p[1] = c.g;
    p[2] = c.b;
  }
};

}  // namespace ffd
