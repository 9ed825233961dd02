// A flipbook's sheet as an engine reads it: a grid of equal cells, each holding one frame (or the
// part of it the whole sequence covers), with a border of empty texels whose colour is bled from the
// frame so that filtering and mipmaps do not fringe. CPU only: puffrender fills it with rendered
// frames.
#pragma once

#include <array>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <puff/cel/frame.h>

#include <puff/core/error.h>
#include <puff/core/image.h>

namespace puff::render {

/// A map written beside a flipbook's sheet (puffrender --maps): the same cells, drawn with the
/// frame output `output` (SceneRenderer::setOutput), the first `channels` channels of the map
/// written as unsigned-normalized data (no transfer function).
struct FlipbookMap {
  std::string_view name;  ///< as --maps and the layout JSON spell it; the file is STEM_name.png
  cel::FrameOutput output;
  int channels;
  std::string_view encoding;  ///< one line for the layout JSON
  float nothing[3];           ///< what a texel no frame covers holds: no surface facing, far, no ink, no motion
};
inline constexpr std::array<FlipbookMap, 4> kFlipbookMaps{{
    {"normal",
     cel::FrameOutput::kNormal,
     3,
     "the flipbook camera's view-space unit normal n as 0.5 n + 0.5: x right, y up (OpenGL convention), z toward "
     "the camera; on a camera-facing quad this is the tangent-space normal (tangent = quad right, bitangent = quad "
     "up)",
     {0.5f, 0.5f, 1.0f}},
    {"depth",
     cel::FrameOutput::kDepth,
     1,
     "0.5 + (targetDistance - d) / (2 depthRange) for the view-axis distance d of the surface drawn: 0.5 at the "
     "camera target's depth, nearer is brighter",
     {0.0f, 0.0f, 0.0f}},
    {"ink",
     cel::FrameOutput::kInk,
     1,
     "the ink's share of the covered texel: colour = mix(lit body, ink colour, ink) where alpha covers",
     {0.0f, 0.0f, 0.0f}},
    {"motion",
     cel::FrameOutput::kMotion,
     3,
     "where the texel's content is at the next frame, m texels away (x right, y up in the image), as R = 0.5 + "
     "m.x / (2 motionRange), G = 0.5 + m.y / (2 motionRange), B = 0",
     {0.5f, 0.5f, 0.0f}},
}};
/// The maps' names, in kFlipbookMaps' order.
std::vector<std::string> flipbookMapNames();
/// The map called `name`, or null.
const FlipbookMap* findFlipbookMap(std::string_view name);

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
