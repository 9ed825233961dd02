// Reads text drawn with support/label.h's font back from an image, glyph by glyph: what a test checks a
// label with (the pixels at each font pixel's centre, brighter than `threshold` on channel 0 set).
#pragma once

#include <string>

#include <puff/core/image.h>
#include <puff/support/label.h>

namespace puff::test {

/// The character whose glyph has its top-left at (x, y) at `scale`, or '\0' if none matches.
inline char readGlyph(const core::Image& image, int x, int y, int scale = 1, float threshold = 0.5f) {
  std::string g;
  for (int row = 0; row < core::kGlyphHeight; ++row) {
    if (row > 0) g += ' ';
    for (int col = 0; col < core::kGlyphWidth; ++col) {
      const int px = x + col * scale + scale / 2, py = y + row * scale + scale / 2;
      const bool set = px >= 0 && py >= 0 && px < image.width && py < image.height && image.at(px, py, 0) > threshold;
      g += set ? '#' : '.';
    }
  }
  for (char c : std::string("0123456789ABCDEFGHIJKLMNOPQRSTUVWXYZ .,:-_/()#%+=?")) {
    if (core::glyph(c) == g) return c;
  }
  return '\0';
}

/// `count` glyphs from (x, y) on.
inline std::string readText(const core::Image& image, int x, int y, int count, int scale = 1, float threshold = 0.5f) {
  std::string s;
  for (int i = 0; i < count; ++i) s += readGlyph(image, x + i * core::kGlyphAdvance * scale, y, scale, threshold);
  return s;
}

}  // namespace puff::test
