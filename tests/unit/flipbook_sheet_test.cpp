// A flipbook sheet's layout (cells, padding, power-of-two sides, the crop), the sequence's coverage
// box and the cells' bled colour, against hand-worked layouts.
#include <gtest/gtest.h>

#include <vector>

#include <puff/render/flipbook.h>

#include "support/assert_ok.h"

namespace puff::render {
namespace {

// A 4-channel frame, alpha 0 but for `rect` (alpha `a`, colour (x, y, 1) / 100 by texel).
core::Image frameWith(int w, int h, PixelRect rect, float a = 1.0f) {
  core::Image f(w, h, 4, 0.0f);
  for (int y = rect.y; y < rect.y + rect.height; ++y)
    for (int x = rect.x; x < rect.x + rect.width; ++x) {
      f.at(x, y, 0) = static_cast<float>(x) / 100.0f;
      f.at(x, y, 1) = static_cast<float>(y) / 100.0f;
      f.at(x, y, 2) = 0.01f;
      f.at(x, y, 3) = a;
    }
  return f;
}

TEST(FlipbookSheet, CellsAreTheFramePlusItsPaddingOnEverySide) {
  // The whole 40x30 frame in a 3x2 grid, 5 texels of padding: cells 50x40, sheet 150x80.
  auto l = layOutSheet({3, 2, {0, 0, 40, 30}, 5, false});
  ASSERT_OK(l);
  EXPECT_EQ(l->cellWidth, 50);
  EXPECT_EQ(l->cellHeight, 40);
  EXPECT_EQ(l->sheetWidth(), 150);
  EXPECT_EQ(l->sheetHeight(), 80);
  EXPECT_EQ(l->offsetX, 5);
  EXPECT_EQ(l->offsetY, 5);
  // Cell 4: column 1, row 1.
  EXPECT_EQ(l->cell(4), (PixelRect{50, 40, 50, 40}));
  // No padding: the cells touch and hold the frame alone.
  auto bare = layOutSheet({3, 2, {0, 0, 40, 30}, 0, false});
  ASSERT_OK(bare);
  EXPECT_EQ(bare->cellWidth, 40);
  EXPECT_EQ(bare->offsetX, 0);
}

TEST(FlipbookSheet, PowerOfTwoSheetsCentreTheFrameInWholeCells) {
  // A 79x74 crop, padding 4: 87x82 a cell, 8x4 of them 696x328, rounded up to 1024x512, so each cell
  // is 128x128 and the frame sits 4 + (128 - 87) / 2 = 24 across, 4 + (128 - 82) / 2 = 27 down.
  auto l = layOutSheet({8, 4, {20, 46, 79, 74}, 4, true});
  ASSERT_OK(l);
  EXPECT_EQ(l->sheetWidth(), 1024);
  EXPECT_EQ(l->sheetHeight(), 512);
  EXPECT_EQ(l->cellWidth, 128);
  EXPECT_EQ(l->cellHeight, 128);
  EXPECT_EQ(l->offsetX, 24);
  EXPECT_EQ(l->offsetY, 27);
  // Already a power of two: unchanged.
  auto exact = layOutSheet({4, 4, {0, 0, 64, 32}, 0, true});
  ASSERT_OK(exact);
  EXPECT_EQ(exact->sheetWidth(), 256);
  EXPECT_EQ(exact->sheetHeight(), 128);
  EXPECT_EQ(exact->offsetX, 0);
  // Every power-of-two grid from 1 to 256 gives power-of-two sides with the frame and its padding inside.
  for (int g = 1; g <= 256; g *= 2) {
    auto r = layOutSheet({g, 256 / g, {0, 0, 100, 60}, 3, true});
    ASSERT_OK(r);
    for (int side : {r->sheetWidth(), r->sheetHeight()}) EXPECT_EQ(side & (side - 1), 0) << g << ": " << side;
    EXPECT_GE(r->offsetX, 3);
    EXPECT_GE(r->cellWidth - r->offsetX - 100, 3);
    EXPECT_GE(r->offsetY, 3);
    EXPECT_GE(r->cellHeight - r->offsetY - 60, 3);
  }
}

TEST(FlipbookSheet, WhatCannotBeLaidOutSaysWhy) {
  auto sixBySix = layOutSheet({6, 6, {0, 0, 128, 128}, 0, true});
  ASSERT_FALSE(sixBySix);
  EXPECT_NE(sixBySix.error().message.find("a 6x6 grid cannot divide a power-of-two sheet"), std::string::npos);
  EXPECT_FALSE(layOutSheet({8, 3, {0, 0, 16, 16}, 0, true}));
  EXPECT_TRUE(layOutSheet({6, 6, {0, 0, 128, 128}, 0, false}));
  EXPECT_FALSE(layOutSheet({2, 2, {0, 0, 16, 16}, -1, false}));
  EXPECT_FALSE(layOutSheet({2, 2, {0, 0, 16, 16}, kMaxSheetPadding + 1, false}));
  EXPECT_TRUE(layOutSheet({2, 2, {0, 0, 16, 16}, kMaxSheetPadding, false}));
  EXPECT_FALSE(layOutSheet({2, 2, {0, 0, 0, 16}, 0, false}));
}

TEST(FlipbookSheet, TheCoverageBoxIsTheUnionOfTheFramesAboveTheThreshold) {
  std::vector<core::Image> frames{frameWith(40, 30, {5, 6, 4, 3}), frameWith(40, 30, {20, 2, 2, 2}),
                                  frameWith(40, 30, {0, 0, 0, 0})};
  EXPECT_EQ(coverageBox(frames, 0.0f), (PixelRect{5, 2, 17, 7}));
  // One texel above the threshold is enough; at it is not.
  frames[2].at(39, 29, 3) = 0.002f;
  EXPECT_EQ(coverageBox(frames, 0.5f / 255.0f), (PixelRect{5, 2, 35, 28}));
  frames[2].at(39, 29, 3) = 0.5f / 255.0f;
  EXPECT_EQ(coverageBox(frames, 0.5f / 255.0f), (PixelRect{5, 2, 17, 7}));
  EXPECT_TRUE(coverageBox(std::vector<core::Image>{frameWith(8, 8, {})}, 0.0f).empty());
  EXPECT_TRUE(covers(frames[0], 0.0f));
  EXPECT_FALSE(covers(frameWith(8, 8, {}), 0.0f));
  EXPECT_FALSE(covers(frameWith(8, 8, {1, 1, 2, 2}, 0.001f), 0.5f / 255.0f));
}

TEST(FlipbookSheet, ACellHoldsTheCropAtItsOffsetAndBleedsItsColourIntoThePadding) {
  const core::Image frame = frameWith(40, 30, {10, 8, 6, 4});
  auto l = layOutSheet({2, 1, {8, 6, 10, 8}, 3, false});
  ASSERT_OK(l);
  for (bool bleed : {false, true}) {
    const core::Image cell = cellOf(frame, *l, bleed);
    ASSERT_EQ(cell.width, 16);
    ASSERT_EQ(cell.height, 14);
    for (int y = 0; y < cell.height; ++y)
      for (int x = 0; x < cell.width; ++x) {
        const int fx = x - l->offsetX + l->crop.x, fy = y - l->offsetY + l->crop.y;
        const bool inFrame = fx >= 8 && fx < 18 && fy >= 6 && fy < 14;
        const bool covered = inFrame && frame.at(fx, fy, 3) > 0.0f;
        EXPECT_EQ(cell.at(x, y, 3), covered ? 1.0f : 0.0f) << x << "," << y;
        if (covered) {
          for (int c = 0; c < 3; ++c) EXPECT_EQ(cell.at(x, y, c), frame.at(fx, fy, c));
        } else if (!bleed) {
          EXPECT_EQ(cell.at(x, y, 0) + cell.at(x, y, 1) + cell.at(x, y, 2), 0.0f) << x << "," << y;
        } else {
          // The nearest covered texel's colour: covered x runs 10-15 and y 8-11 in the frame.
          const int nx = std::clamp(fx, 10, 15), ny = std::clamp(fy, 8, 11);
          EXPECT_EQ(cell.at(x, y, 0), frame.at(nx, ny, 0)) << x << "," << y;
          EXPECT_EQ(cell.at(x, y, 1), frame.at(nx, ny, 1)) << x << "," << y;
        }
      }
  }
  // placeCell puts it at the cell's rectangle and nowhere else.
  core::Image sheet(l->sheetWidth(), l->sheetHeight(), 4, -1.0f);
  const core::Image cell = cellOf(frame, *l, false);
  placeCell(sheet, *l, 1, cell);
  EXPECT_EQ(sheet.at(15, 0, 0), -1.0f);
  EXPECT_EQ(sheet.at(16, 0, 0), cell.at(0, 0, 0));
  EXPECT_EQ(sheet.at(16 + 5, 5, 3), cell.at(5, 5, 3));
  EXPECT_EQ(sheet.at(31, 13, 3), cell.at(15, 13, 3));
}

}  // namespace
}  // namespace puff::render
