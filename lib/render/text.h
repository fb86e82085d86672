// Text on an Image in a built-in bitmap font: 5 × 7 pixel glyphs (capitals and digits
// 7 high, lowercase 5 high with 2 rows of descender) in a 6 × 9 cell, one line, for
// labels and numbers over a rendered picture.
//
// Metrics at scale s: each character is 6·s pixels wide, the last one's blank column
// not counted (a text of n characters is (6·n − 1)·s wide); a line is 9·s high, with
// the baseline 7·s below its top. Characters are UTF-8 sequences. The font has space,
// 0-9, A-Z, a-z and . , : ; - + = % ( ) / _ < > # ! ? ' * [ ] |; any other character
// (a tab, a "×") draws as a small box.
#pragma once

#include <string_view>

#include "render/image.h"

namespace ffd {

/// The width of `text` in pixels at `scale` (a scale below 1 counts as 1); 0 for no text.
int text_width(std::string_view text, int scale);

/// The height of a line in pixels at `scale` (a scale below 1 counts as 1).
int text_height(int scale);

/// Draws `text` with its cell's top-left at (x, y), each font pixel a scale × scale
/// square in `color`; only the glyphs' pixels are written. Clipped to the image: any x
/// and y (negative, past the image) are fine.
void draw_text(Image& image, int x, int y, std::string_view text, Rgb color, int scale = 1);

/// draw_text over a filled `background` rectangle: the text's text_width × text_height
/// with a margin of 2·scale pixels on each side, so the rectangle's top-left is at
/// (x − 2·scale, y − 2·scale). Draws nothing for no text. Clipped like draw_text.
void draw_text_box(Image& image, int x, int y, std::string_view text, Rgb color, Rgb background, int scale = 1);

}  // namespace ffd
