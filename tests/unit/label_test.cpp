// The built-in font for labels on contact sheets (support/label.h): every glyph well formed and unlike
// every other, and text drawn at any scale reads back, glyph by glyph, as the text it was given.
#include <gtest/gtest.h>

#include <set>
#include <string>

#include <puff/support/label.h>

#include "support/read_text.h"

namespace puff::core {
namespace {

const std::string kAll = "0123456789ABCDEFGHIJKLMNOPQRSTUVWXYZ .,:-_/()#%+=?";

TEST(Label, EveryGlyphIsSevenRowsOfFiveAndNoTwoAlike) {
  std::set<std::string> seen;
  for (char c : kAll) {
    ASSERT_TRUE(hasGlyph(c)) << c;
    const std::string g(glyph(c));
    ASSERT_EQ(g.size(), 7u * 6u - 1u) << c;
    for (std::size_t i = 0; i < g.size(); ++i) {
      if (i % 6 == 5) {
        EXPECT_EQ(g[i], ' ') << c << " at " << i;
      } else {
        EXPECT_TRUE(g[i] == '#' || g[i] == '.') << c << " at " << i;
      }
    }
    EXPECT_TRUE(seen.insert(g).second) << c << " looks like another glyph";
    // Every glyph but the space sets a pixel.
    if (c != ' ') {
      EXPECT_NE(g.find('#'), std::string::npos) << c;
    }
  }
  EXPECT_EQ(glyph('q'), glyph('Q')) << "lower case is drawn as capitals";
  EXPECT_FALSE(hasGlyph('~'));
  EXPECT_EQ(glyph('~'), glyph('?')) << "a character the font lacks is drawn as '?'";
}

using test::readGlyph;

TEST(Label, TextReadsBackAtEveryScaleAndStaysInItsBox) {
  const std::string text = "Frame 0042: (3x3) 95% a/b_c-d+e=f.g,h#?";
  for (int scale : {1, 2, 3}) {
    const int x0 = 5, y0 = 4;
    Image image(textWidth(text, scale) + 10, textHeight(scale) + 8, 3, 0.0f);
    drawText(image, x0, y0, text, glm::vec3(1.0f), scale);
    std::string read;
    for (std::size_t i = 0; i < text.size(); ++i) {
      read += readGlyph(image, x0 + static_cast<int>(i) * kGlyphAdvance * scale, y0, scale);
    }
    std::string upper = text;
    for (char& c : upper) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    EXPECT_EQ(read, upper) << "scale " << scale;
    // Nothing outside the text's box.
    for (int y = 0; y < image.height; ++y)
      for (int x = 0; x < image.width; ++x) {
        const bool inside = x >= x0 && x < x0 + textWidth(text, scale) && y >= y0 && y < y0 + textHeight(scale);
        if (!inside) {
          ASSERT_EQ(image.at(x, y, 0), 0.0f) << "scale " << scale << " at " << x << "," << y;
        }
      }
    EXPECT_EQ(image.at(0, 0, 1), 0.0f);
  }
}

TEST(Label, ALabelIsTextOnABoxAndClipsAtTheImagesEdges) {
  Image image(40, 20, 4, 0.0f);
  const int w = drawLabel(image, 2, 3, "12", glm::vec3(1.0f, 1.0f, 0.0f), glm::vec3(0.0f, 0.0f, 1.0f), 1);
  EXPECT_EQ(w, textWidth("12") + 2);
  EXPECT_EQ(textWidth("12"), 11);
  // The box: blue and opaque from (2, 3) to (2 + w, 3 + 9); the text inside is yellow.
  EXPECT_EQ(image.at(2, 3, 2), 1.0f);
  EXPECT_EQ(image.at(2, 3, 3), 1.0f);
  EXPECT_EQ(image.at(2 + w - 1, 3 + 8, 2), 1.0f);
  EXPECT_EQ(image.at(2 + w, 3, 3), 0.0f);
  EXPECT_EQ(image.at(2, 3 + 9, 3), 0.0f);
  EXPECT_EQ(readGlyph(image, 3, 4, 1), '1');
  EXPECT_EQ(readGlyph(image, 3 + kGlyphAdvance, 4, 1), '2');
  // Text past any edge draws what fits and nothing else.
  for (const auto& [x, y] : {std::pair{-7, -3}, std::pair{35, 15}, std::pair{-100, 100}}) {
    drawLabel(image, x, y, "EDGE", glm::vec3(1.0f), glm::vec3(0.5f), 3);
  }
  EXPECT_EQ(image.at(0, 0, 3), 1.0f);
  Image grey(4, 4, 1, 0.0f);
  drawText(grey, 0, 0, "8", glm::vec3(1.0f));  // fewer than 3 channels: nothing to draw in
  EXPECT_EQ(grey.at(1, 1), 0.0f);
}

}  // namespace
}  // namespace puff::core
