// Text on images for people to read: frame numbers on a sequence's contact sheet, column titles on an
// atlas's. A built-in 5 x 7 pixel font (capitals, digits and a little punctuation; lower case is drawn
// as capitals), so no font file or library is needed and every machine draws the same pixels.
#pragma once

#include <string_view>

#include <glm/vec3.hpp>

#include <puff/core/image.h>

namespace puff::core {

inline constexpr int kGlyphWidth = 5, kGlyphHeight = 7;
inline constexpr int kGlyphAdvance = kGlyphWidth + 1;  ///< a column of space between glyphs

/// The glyph for `c`: 7 rows of 5 columns, '#' set and '.' clear, top row first, rows separated
/// by a space. Lower case gives
/// the capital; a character the font lacks gives '?'.
std::string_view glyph(char c);
/// Whether the font has `c` (or its capital).
bool hasGlyph(char c);

/// Pixels `text` spans at `scale` (each font pixel a scale x scale block): width, one line high.
int textWidth(std::string_view text, int scale = 1);
inline int textHeight(int scale = 1) { return kGlyphHeight * scale; }

/// Draws `text` with its top-left corner at (x, y), in `color` on the first three channels (a
/// fourth, alpha, is set to 1); pixels outside the image are skipped.
void drawText(Image& image, int x, int y, std::string_view text, glm::vec3 color, int scale = 1);

/// A label: `text` on a box of `background` reaching `scale` pixels past it on every side, so it
/// reads over any picture. Returns the box's width.
int drawLabel(Image& image, int x, int y, std::string_view text, glm::vec3 color, glm::vec3 background, int scale = 1);

}  // namespace puff::core
