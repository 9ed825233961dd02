// puff::io: image files through OpenImageIO (PNG, EXR, TIFF, JPEG, ... whatever the installed
// OpenImageIO reads and writes), for the programs that read artists' files: Puff's tools, and a game
// that loads uncooked assets. puff::core itself reads and writes only cooked images (".puffimg",
// core/image.h); a game that ships cooked assets needs neither this component nor OpenImageIO.
#pragma once

#include <puff/core/image.h>

namespace puff::io {

/// The OpenImageIO codec: reads any format OpenImageIO knows, values as stored (no division by a
/// fourth channel that may not be alpha), and the file's "puff:" string attributes; writes with
/// the attributes in the file's metadata, float formats zip-compressed, with no time stamp (the
/// same inputs give the same bytes).
const core::ImageCodec& openImageIOCodec();

/// Installs openImageIOCodec() for every later core::readImage / core::writeImage
/// (core::setImageCodec). Call it first thing in main.
void useOpenImageIO();

}  // namespace puff::io
