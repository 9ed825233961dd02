#include <puff/support/label.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <utility>

namespace puff::core {

namespace {

// Each glyph's 7 rows of 5 pixels from the top, separated by spaces: '#' set, '.' clear.
constexpr std::array<std::pair<char, std::string_view>, 50> kGlyphs{{
    {' ', "..... ..... ..... ..... ..... ..... ....."}, {'#', ".#.#. .#.#. ##### .#.#. ##### .#.#. .#.#."},
    {'%', "##... ##..# ...#. ..#.. .#... #..## ...##"}, {'(', "...#. ..#.. .#... .#... .#... ..#.. ...#."},
    {')', ".#... ..#.. ...#. ...#. ...#. ..#.. .#..."}, {'+', "..... ..#.. ..#.. ##### ..#.. ..#.. ....."},
    {',', "..... ..... ..... ..... .##.. ..#.. .#..."}, {'-', "..... ..... ..... ##### ..... ..... ....."},
    {'.', "..... ..... ..... ..... ..... .##.. .##.."}, {'/', "..... ....# ...#. ..#.. .#... #.... ....."},
    {'0', ".###. #...# #..## #.#.# ##..# #...# .###."}, {'1', "..#.. .##.. ..#.. ..#.. ..#.. ..#.. .###."},
    {'2', ".###. #...# ....# ...#. ..#.. .#... #####"}, {'3', "##### ...#. ..#.. ...#. ....# #...# .###."},
    {'4', "...#. ..##. .#.#. #..#. ##### ...#. ...#."}, {'5', "##### #.... ####. ....# ....# #...# .###."},
    {'6', "..##. .#... #.... ####. #...# #...# .###."}, {'7', "##### ....# ...#. ..#.. .#... .#... .#..."},
    {'8', ".###. #...# #...# .###. #...# #...# .###."}, {'9', ".###. #...# #...# .#### ....# ...#. .##.."},
    {':', "..... .##.. .##.. ..... .##.. .##.. ....."}, {'=', "..... ..... ##### ..... ##### ..... ....."},
    {'?', ".###. #...# ....# ...#. ..#.. ..... ..#.."}, {'A', ".###. #...# #...# ##### #...# #...# #...#"},
    {'B', "####. #...# #...# ####. #...# #...# ####."}, {'C', ".###. #...# #.... #.... #.... #...# .###."},
    {'D', "###.. #..#. #...# #...# #...# #..#. ###.."}, {'E', "##### #.... #.... ####. #.... #.... #####"},
    {'F', "##### #.... #.... ####. #.... #.... #...."}, {'G', ".###. #...# #.... #.### #...# #...# .####"},
    {'H', "#...# #...# #...# ##### #...# #...# #...#"}, {'I', ".###. ..#.. ..#.. ..#.. ..#.. ..#.. .###."},
    {'J', "..### ...#. ...#. ...#. ...#. #..#. .##.."}, {'K', "#...# #..#. #.#.. ##... #.#.. #..#. #...#"},
    {'L', "#.... #.... #.... #.... #.... #.... #####"}, {'M', "#...# ##.## #.#.# #.#.# #...# #...# #...#"},
    {'N', "#...# #...# ##..# #.#.# #..## #...# #...#"}, {'O', ".###. #...# #...# #...# #...# #...# .###."},
    {'P', "####. #...# #...# ####. #.... #.... #...."}, {'Q', ".###. #...# #...# #...# #.#.# #..#. .##.#"},
    {'R', "####. #...# #...# ####. #.#.. #..#. #...#"}, {'S', ".#### #.... #.... .###. ....# ....# ####."},
    {'T', "##### ..#.. ..#.. ..#.. ..#.. ..#.. ..#.."}, {'U', "#...# #...# #...# #...# #...# #...# .###."},
    {'V', "#...# #...# #...# #...# #...# .#.#. ..#.."}, {'W', "#...# #...# #...# #.#.# #.#.# #.#.# .#.#."},
    {'X', "#...# #...# .#.#. ..#.. .#.#. #...# #...#"}, {'Y', "#...# #...# .#.#. ..#.. ..#.. ..#.. ..#.."},
    {'Z', "##### ....# ...#. ..#.. .#... #.... #####"}, {'_', "..... ..... ..... ..... ..... ..... #####"},
}};

std::string_view find(char c) {
  const char upper = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  for (const auto& [ch, rows] : kGlyphs) {
    if (ch == upper) return rows;
  }
  return {};
}

}  // namespace

std::string_view glyph(char c) {
  const std::string_view g = find(c);
  return g.empty() ? find('?') : g;
}

bool hasGlyph(char c) { return !find(c).empty(); }

int textWidth(std::string_view text, int scale) {
  if (text.empty()) return 0;
  return (static_cast<int>(text.size()) * kGlyphAdvance - 1) * scale;
}

void drawText(Image& image, int x, int y, std::string_view text, glm::vec3 color, int scale) {
  if (image.channels < 3) return;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const std::string_view g = glyph(text[i]);
    const int gx = x + static_cast<int>(i) * kGlyphAdvance * scale;
    for (int row = 0; row < kGlyphHeight; ++row) {
      for (int col = 0; col < kGlyphWidth; ++col) {
        if (g[static_cast<std::size_t>(row * (kGlyphWidth + 1) + col)] != '#') continue;
        for (int sy = 0; sy < scale; ++sy) {
          for (int sx = 0; sx < scale; ++sx) {
            const int px = gx + col * scale + sx, py = y + row * scale + sy;
            if (px < 0 || py < 0 || px >= image.width || py >= image.height) continue;
            for (int c = 0; c < 3; ++c) image.at(px, py, c) = color[c];
            if (image.channels == 4) image.at(px, py, 3) = 1.0f;
          }
        }
      }
    }
  }
}

int drawLabel(Image& image, int x, int y, std::string_view text, glm::vec3 color, glm::vec3 background, int scale) {
  const int w = textWidth(text, scale) + 2 * scale, h = textHeight(scale) + 2 * scale;
  if (image.channels >= 3) {
    for (int py = std::max(0, y); py < std::min(image.height, y + h); ++py) {
      for (int px = std::max(0, x); px < std::min(image.width, x + w); ++px) {
        for (int c = 0; c < 3; ++c) image.at(px, py, c) = background[c];
        if (image.channels == 4) image.at(px, py, 3) = 1.0f;
      }
    }
  }
  drawText(image, x + scale, y + scale, text, color, scale);
  return w;
}

}  // namespace puff::core
