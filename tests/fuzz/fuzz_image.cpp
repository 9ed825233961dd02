// libFuzzer harness: an image file in one use (PUFF_FUZZ_IMAGE_USE): a ramp or a gradient as the cel
// path reads them (without GL), or a detail clip as the media path reads it. The first byte picks
// the file's extension (.png, .exr, .puffimg); the rest is the file.
#include <puff/cel/frame.h>
#include <puff/core/detail_video.h>

#include "fuzz_common.h"

#define PUFF_USE_RAMP 1
#define PUFF_USE_GRADIENT 2
#define PUFF_USE_DETAIL 3

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  puff::io::useOpenImageIO();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  const auto file =
      puff::fuzz::writeInput(std::string("image") + puff::fuzz::imageExtension(data[0]), data + 1, size - 1);
#if PUFF_FUZZ_IMAGE_USE == PUFF_USE_RAMP
  puff::fuzz::expectCleanError(puff::cel::Ramp::read(file));
#elif PUFF_FUZZ_IMAGE_USE == PUFF_USE_GRADIENT
  puff::fuzz::expectCleanError(puff::cel::Gradient::read(file));
#elif PUFF_FUZZ_IMAGE_USE == PUFF_USE_DETAIL
  puff::fuzz::expectCleanError(puff::core::loadDetailVideo(file));
#else
#error "PUFF_FUZZ_IMAGE_USE must be PUFF_USE_RAMP, PUFF_USE_GRADIENT or PUFF_USE_DETAIL"
#endif
  std::error_code ec;
  std::filesystem::remove(file, ec);  // the next input may take another extension
  return 0;
}
