// libFuzzer harness: a scene file, read as puffrender and puffview read it (scene::loadScene).
#include <puff/scene/read.h>

#include "fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto file = puff::fuzz::writeInput("scene.json", data, size);
  puff::fuzz::expectCleanError(puff::scene::loadScene(file, PUFF_FUZZ_ART_DIR));
  return 0;
}
