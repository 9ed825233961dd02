// A flipbook's sheet as an engine reads it: a grid of equal cells, each holding one frame (or the
// part of it the whole sequence covers), with a border of empty texels whose colour is bled from the
// frame so that filtering and mipmaps do not fringe. CPU only: puffrender fills it with rendered
// frames.
#pragma once

#include <span>

#include <puff/core/error.h>
#include <puff/core/image.h>

namespace puff::render {

/// A rectangle of texels, origin at the top-left.
struct PixelRect {
  int x = 0, y = 0, width = 0, height = 0;
  bool empty() const { return width <= 0 || height <= 0; }
  bool operator==(const PixelRect&) const = default;
};

/// The most texels of padding around each frame in its cell (--padding).
inline constexpr int kMaxSheetPadding = 256;

/// What a sheet is asked to be.
struct SheetRequest {
  int columns = 1, rows = 1;
  PixelRect crop;     ///< the part of every rendered frame the cells hold (the whole frame without --crop)
  int padding = 0;    ///< empty texels around the frame on every side inside its cell, [0, kMaxSheetPadding]
  bool pow2 = false;  ///< the sheet's sides powers of two (the grid's must be too, so cells stay whole texels)
};

/// Where everything lies on the sheet. Every cell is the same size and the cells tile the sheet
/// exactly (columns x cellWidth by rows x cellHeight), so an engine that divides the texture evenly
/// by the grid finds each cell; the frame sits at the same offset in every cell.
struct SheetLayout {
  int columns = 1, rows = 1;
  int cellWidth = 0, cellHeight = 0;
  PixelRect crop;                ///< of each rendered frame, the part in its cell
  int offsetX = 0, offsetY = 0;  ///< the crop's top-left inside its cell (the padding, plus --pow2's margin)
  int padding = 0;
  bool pow2 = false;
  int sheetWidth() const { return columns * cellWidth; }
  int sheetHeight() const { return rows * cellHeight; }
  /// Cell `i`'s rectangle on the sheet: column i % columns, row i / columns, row 0 at the top.
  PixelRect cell(int i) const;
};

/// The layout for `request`; an error (no "--" option names: the caller's) for padding out of range,
/// --pow2 with a grid that is not a power of two on each side, or an empty crop.
Result<SheetLayout> layOutSheet(const SheetRequest& request);

/// The smallest rectangle holding every texel whose alpha (channel 3) is above `threshold` in any of
/// `frames` (all the same size, 4 channels); empty when none is.
PixelRect coverageBox(std::span<const core::Image> frames, float threshold);

/// Whether any texel's alpha is above `threshold`.
bool covers(const core::Image& frame, float threshold);

/// Every texel whose alpha is at most `covered` (what the sheet's encoding stores as 0) takes the
/// colour of the nearest texel above it (breadth first over the 4 neighbours); alpha and covered
/// texels are untouched. For straight-alpha cells: an engine's filter then mixes the smoke's colour
/// with its own, not with black.
void bleedColour(core::Image& cell, float covered = 0.0f);

/// Cell-sized image of `frame` (4 channels) as the layout places it: the crop at the offset, zero
/// (alpha 0) elsewhere; with `bleed`, bleedColour(`covered`) over the whole cell, padding included.
core::Image cellOf(const core::Image& frame, const SheetLayout& layout, bool bleed, float covered = 0.0f);

/// Copies `cell` (cellWidth x cellHeight, 4 channels) into cell `i` of `sheet`.
void placeCell(core::Image& sheet, const SheetLayout& layout, int i, const core::Image& cell);

}  // namespace puff::render
