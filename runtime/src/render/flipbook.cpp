#include <puff/render/flipbook.h>

#include <algorithm>
#include <string>
#include <vector>

namespace puff::render {

namespace {

bool isPowerOfTwo(long long n) { return n > 0 && (n & (n - 1)) == 0; }

long long nextPowerOfTwo(long long n) {
  long long p = 1;
  while (p < n) p <<= 1;
  return p;
}

}  // namespace

std::vector<std::string> flipbookMapNames() {
  std::vector<std::string> names;
  for (const FlipbookMap& m : kFlipbookMaps) names.emplace_back(m.name);
  return names;
}

const FlipbookMap* findFlipbookMap(std::string_view name) {
  for (const FlipbookMap& m : kFlipbookMaps) {
    if (m.name == name) return &m;
  }
  return nullptr;
}

PixelRect SheetLayout::cell(int i) const {
  return {(i % columns) * cellWidth, (i / columns) * cellHeight, cellWidth, cellHeight};
}

Result<SheetLayout> layOutSheet(const SheetRequest& r) {
  if (r.padding < 0 || r.padding > kMaxSheetPadding) {
    return Error{"padding " + std::to_string(r.padding) + " is outside [0, " + std::to_string(kMaxSheetPadding) +
                 "] texels"};
  }
  if (r.crop.empty()) return Error{"the frames' crop is empty: nothing to place in the cells"};
  if (r.pow2 && (!isPowerOfTwo(r.columns) || !isPowerOfTwo(r.rows))) {
    return Error{"a " + std::to_string(r.columns) + "x" + std::to_string(r.rows) +
                 " grid cannot divide a power-of-two sheet into cells of whole texels: give a power-of-two "
                 "grid (4x4, 8x8, 8x4...)"};
  }
  SheetLayout l;
  l.columns = r.columns;
  l.rows = r.rows;
  l.crop = r.crop;
  l.padding = r.padding;
  l.pow2 = r.pow2;
  long long cellW = r.crop.width + 2ll * r.padding, cellH = r.crop.height + 2ll * r.padding;
  if (r.pow2) {
    // The sheet rounds up to a power of two, and with a power-of-two grid each cell is one too: the
    // margin this adds is split around the frame, which stays centred in its cell to within a texel.
    cellW = nextPowerOfTwo(cellW * r.columns) / r.columns;
    cellH = nextPowerOfTwo(cellH * r.rows) / r.rows;
  }
  l.cellWidth = static_cast<int>(cellW);  // within int: a grid is at most 256 a side, a crop one frame
  l.cellHeight = static_cast<int>(cellH);
  l.offsetX = r.padding + (l.cellWidth - r.crop.width - 2 * r.padding) / 2;
  l.offsetY = r.padding + (l.cellHeight - r.crop.height - 2 * r.padding) / 2;
  return l;
}

PixelRect coverageBox(std::span<const core::Image> frames, float threshold) {
  int x0 = 1 << 30, y0 = 1 << 30, x1 = -1, y1 = -1;
  for (const core::Image& f : frames) {
    for (int y = 0; y < f.height; ++y) {
      for (int x = 0; x < f.width; ++x) {
        if (f.at(x, y, 3) <= threshold) continue;
        x0 = std::min(x0, x), x1 = std::max(x1, x);
        y0 = std::min(y0, y), y1 = std::max(y1, y);
      }
    }
  }
  if (x1 < 0) return {};
  return {x0, y0, x1 - x0 + 1, y1 - y0 + 1};
}

bool covers(const core::Image& frame, float threshold) {
  for (std::size_t i = 3; i < frame.pixels.size(); i += 4) {
    if (frame.pixels[i] > threshold) return true;
  }
  return false;
}

void bleedColour(core::Image& cell, float covered) {
  const int w = cell.width, h = cell.height;
  std::vector<int> queue;
  std::vector<char> filled(static_cast<std::size_t>(w) * h, 0);
  for (int i = 0; i < w * h; ++i) {
    if (cell.pixels[static_cast<std::size_t>(i) * 4 + 3] > covered)
      filled[static_cast<std::size_t>(i)] = 1, queue.push_back(i);
  }
  for (std::size_t q = 0; q < queue.size(); ++q) {
    const int i = queue[q], x = i % w, y = i / w;
    const int next[4] = {x > 0 ? i - 1 : -1, x + 1 < w ? i + 1 : -1, y > 0 ? i - w : -1, y + 1 < h ? i + w : -1};
    for (int n : next) {
      if (n < 0 || filled[static_cast<std::size_t>(n)]) continue;
      filled[static_cast<std::size_t>(n)] = 1;
      for (std::size_t c = 0; c < 3; ++c) {
        cell.pixels[static_cast<std::size_t>(n) * 4 + c] = cell.pixels[static_cast<std::size_t>(i) * 4 + c];
      }
      queue.push_back(n);
    }
  }
}

core::Image cellOf(const core::Image& frame, const SheetLayout& l, bool bleed, float covered) {
  core::Image cell(l.cellWidth, l.cellHeight, 4, 0.0f);
  for (int y = 0; y < l.crop.height; ++y) {
    std::copy_n(&frame.pixels[frame.index(l.crop.x, l.crop.y + y)], static_cast<std::size_t>(l.crop.width) * 4,
                &cell.pixels[cell.index(l.offsetX, l.offsetY + y)]);
  }
  if (bleed) bleedColour(cell, covered);
  return cell;
}

void placeCell(core::Image& sheet, const SheetLayout& l, int i, const core::Image& cell) {
  const PixelRect r = l.cell(i);
  for (int y = 0; y < r.height; ++y) {
    std::copy_n(&cell.pixels[cell.index(0, y)], static_cast<std::size_t>(r.width) * 4,
                &sheet.pixels[sheet.index(r.x, r.y + y)]);
  }
}

}  // namespace puff::render
